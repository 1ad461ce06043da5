"""GFMD, the production method: Green's function molecular dynamics of the surface (seed §2).

One load step is one problem (`problem`: elastic energy in Fourier space, the interface law, the
hard wall's constraint) solved by algorithms, one module each (`algorithms`), chosen and chained
per law (`chains.relax`; `solver` keeps the old import names); `loading.run_realization` runs the
load ramp of one realization. It imports the core (`contact`) only.
"""

from . import heap as _heap

_heap.keep_heap()  # glibc keeps a step's arrays on its heap (`gfmd.heap`: measured, docs/design/performance.md)
