"""The neutral core every method shares: what a scene is and what a result means.

Units: SI (see `gfmd_contact.core.conventions`). Modules: `scene` (TOML → validated
dataclasses), `conventions` (signs, gaps, Fourier convention), `surfaces`
(profiles, seed Eq. 4; `surfaces_2d`: 2+1-D surfaces), `laws` (traction–separation, seed Eqs. 2–3), `kernels`
(elastic surface stiffness of a half-plane or bonded layer), `model` (what a
scene requires, and why; the checks), `observables` (p, a_rel, ḡ_r), `result`
(the one Result shape), `loading` (the load protocol: steps, stops, warnings).
The methods (`gfmd`, `reference.fem`, `reference.analytic`) import this package
and never each other; the application layer (`gfmd_contact.app`) sits above them.
"""
