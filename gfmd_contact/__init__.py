"""gfmd-contact from Python: build a scene, run it, read the curves, run a study, draw the figures.

``import gfmd_contact as gc``. Units are SI throughout (m, Pa, J/m²; p > 0 compressive;
`gfmd_contact.core.conventions`). Everything the ``gfmd`` command does goes through these functions
or the same code underneath, and a result is a directory the command line reads too.

Scenes (frozen, validated; errors name the key)::

    scene = gc.default_scene()                      # or gc.example_scene(), gc.load_scene("s.toml" | text | dict)
    scene = gc.change(scene, {"surface.nodes": 1024, "interface.phi_n_star": 0.05})
    found, notes = gc.check(scene)                  # the warnings and notes of `gfmd run`, before any work
    gc.stickiness(scene)                            # process zone, Johnson α, Maugis λ, ... (n/a with the reason)

Runs::

    res = gc.run(scene, out="runs/a", method="gfmd", realizations=2, workers=1, plot=True)  # plot: runs/a/plots/
    res = gc.run(scene)  # no out: a temporary directory that goes with res (res.save("runs/b") keeps it)
    res.curve            # pandas DataFrame of curve.csv: realization, seed, step, U, delta (m), p (Pa), a_rel, ...
    res.mean_curve       # DataFrame: per step, mean, standard error (_se) and count (_n) over realizations
    res.fields(0, step)  # dict of arrays: x, h, u_z, u_x, gap (m), t_n, t_t (Pa)
    res.meta             # dict of meta.json (method, model, messages, timings)
    gc.open_run("runs/a")                           # the same for an existing run directory

A user-defined interface law (normal-only; GFMD and the FE evaluate the callables, vectorised, SI)::

    law = gc.user_law(energy=V, traction=T, tangent=dT, length=1e-9, name="my law")  # J/m², Pa (> 0 tensile), Pa/m
    res = gc.run(scene, law=law)    # or gc.with_law(scene, law); scene.toml says interface.law = "user"

Studies (a grid of scenes × realizations on Dask)::

    study = gc.make_study(scene, axes={"interface.phi_n_star": [0.01, 0.15]}, zip=None)
    st = gc.run_study(study, out="runs/s", workers=2)   # or a study TOML file
    st.summary           # xarray Dataset of summary.nc: dims = the axes and step
    st.table             # DataFrame of study.csv; gc.open_study("runs/s") reads it back

Figures (the seed's)::

    gc.run_figures(res), gc.study_figures(st)       # {name: matplotlib Figure}
    gc.plot_run(res), gc.plot_study(st)             # written as files; returns their paths
"""

import importlib

#: public name → the module that defines it. Imported on first use (PEP 562), so that
#: ``import gfmd_contact.core`` (what the methods import) does not pull in the application layer.
_PUBLIC = {
    "Scene": "gfmd_contact.core.scene", "SceneError": "gfmd_contact.core.scene",
    "UserLaw": "gfmd_contact.core.user_law", "UserLawError": "gfmd_contact.core.user_law",
    "user_law": "gfmd_contact.core.user_law",
    "RunDirError": "gfmd_contact.app.io", "StudyError": "gfmd_contact.app.study",
    **dict.fromkeys(["plot_run", "plot_study", "run_figures", "study_figures"], "gfmd_contact.figures"),
    **dict.fromkeys(["RunResult", "open_run", "run", "with_law"], "gfmd_contact.runs"),
    **dict.fromkeys(["change", "check", "default_scene", "example_scene", "load_scene", "save_scene", "scene_dict",
                     "scene_toml", "stickiness"], "gfmd_contact.scenes"),
    **dict.fromkeys(["StudyResult", "load_study", "make_study", "open_study", "run_study", "study_text"],
                    "gfmd_contact.studies"),
}


def __getattr__(name):
    if name in _PUBLIC:
        value = getattr(importlib.import_module(_PUBLIC[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'gfmd_contact' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_PUBLIC))


__all__ = ["Scene", "SceneError", "RunDirError", "StudyError", "default_scene", "example_scene",
           "load_scene", "change", "check", "stickiness", "save_scene", "scene_dict", "scene_toml", "run", "open_run",
           "RunResult", "make_study", "study_text", "load_study", "run_study", "open_study", "StudyResult",
           "run_figures", "plot_run", "study_figures", "plot_study", "user_law", "with_law", "UserLaw", "UserLawError"]
