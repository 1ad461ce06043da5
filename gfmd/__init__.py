"""GFMD, the production method: Green's function molecular dynamics of the surface (seed §2).

`solver` relaxes one load step (FIRE on mass-weighted modes, damped Verlet,
hard-wall projection) on the model of `contact.model`; `loading.run_realization`
runs the load ramp of one realization. It imports the core (`contact`) only.
"""
