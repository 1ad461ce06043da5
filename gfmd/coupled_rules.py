"""The coupled chains' rules (`gfmd.chains`): budgets, break-offs and acceptance distances, each with the measurement
that set it. Read by `gfmd.chains` (under these names; tests patch them there)."""

#: FIRE iterations a coupled-law step gets before the Newton–Krylov / damped-Verlet fallback. Measured (layer
#: D = L, sinusoid a = 50 nm, φn* = 0.01, c = 0.5, ν = 0.3): FIRE needs ≤ 790 iterations per step
#: up to δ = 32 nm (N = 64; ≤ 350 at N = 128), then 950, 7 580, 33 060 and fails (residual 1e-2 to
#: 1e2 p_ref) from δ ≈ 39 nm (N = 128), where Verlet converges in 500–1 140. Budget ≈ 2.5 × 790.
COUPLED_FIRE_BUDGET = 2000
#: FIRE from a handover state (residual ≤ Settings.coupled_handover, Newton's state there rejected or not converged)
#: gets COUPLED_FIRE_CRAWL iterations with the handover link's: near a fold the equilibrium FIRE was approaching is
#: gone, and it crawls through the fold's ghost at residuals 1e-6 to 1e-5 p_ref, moving slowly, before the snap.
#: Measured (Fig. 8 at 2^17, ν = 0.45, c = 0.5, seed 8, step 156): 6 220 iterations after the handover, moves
#: 0.10 → 0.16 δn over the first 5 000, then a 2.38 δn snap, converged (60 CPU s); with COUPLED_FIRE_BUDGET's
#: 1 720 left, every other link stalled at 2e-6 p_ref beside it and damped Verlet ran over an hour. ≈ 3 × 6 220.
COUPLED_FIRE_CRAWL = 20000
#: Newton-first coupled chain: its converged state is kept only where no node moved COUPLED_JUMP · (the law's
#: length, min(δn, δt)) or more from the step's start: the continuation of the stable branch the ramp is on.
#: A larger move (a snap or slip event) hands the step to the FIRE chain, whose Newton is tested for stability
COUPLED_JUMP = 1.0
#: the continuation Newton gives up after COUPLED_CONTINUATION_ITERATIONS iterations: a continuation converges in a
#: few from the ramp's extrapolated guess (Fig. 8 study at 2^17, 772 kept continuation steps of five tasks: at most 11
#: iterations, 98 % ≤ 4), while a step whose Newton wanders ran its 60 (seed 8, step 104: 3 721 FFT pairs, then
#: FIRE and Newton finished it in 443)
COUPLED_CONTINUATION_ITERATIONS = 20
#: and each of its GMRES solves gets COUPLED_CONTINUATION_GMRES_CYCLES restart cycles (of 60 products): the solves of
#: kept continuations took ≤ 104 products (Fig. 8 at 2^17, seed 7, steps 161–198), while on event steps they grew to
#: 150–300 or missed after all 5 cycles (305 FFT pairs) before the continuation was given up anyway
COUPLED_CONTINUATION_GMRES_CYCLES = 2
#: and it gives up once two iterations in a row each left more than COUPLED_CONTINUATION_STAGNATION of the residual
#: before them (a Newton crawling along a near-singular tangent, which went on to the iteration cap or a line search
#: stall: Fig. 8 at 2^17, ν = 0.45, seed 7, step 122: 1.4e-2 p_ref for 17 iterations, 14 of the step's 17 CPU s);
#: kept continuations converge superlinearly (docs/design/performance.md)
COUPLED_CONTINUATION_STAGNATION = 0.5
#: coupled chains: where the ramp extrapolated the step's guess from its last two states (`relax`'s `previous`, the
#: last one), the chain starts from the last state where the guess's nodal force residual is more than
#: COUPLED_START_MARGIN times the last state's: through a snap the extrapolation carries the snapped nodes on into the
#: indenter (Fig. 8 at 2^17, the steps after an event: 7.5 to 2e4 p_ref against 0.3–0.5 from the last state), where
#: the continuation Newton moves a node a law length and hands the step to FIRE; from the last state it is a
#: continuation, the same state within 3e-7 δn. A guess 1.5–1.7× worse was no overshoot: from it the continuation did
#: as well or better (moves from the last state reach a law length sooner), hence the margin
#: (docs/design/performance.md)
COUPLED_BETTER_START = True
COUPLED_START_MARGIN = 2.0
#: handover chains ("handover-near", "frictionless-first"): Newton's state from FIRE's handover state is kept only where no node
#: moved COUPLED_HANDOVER_MOVE · min(δn, δt) or more from it (the equilibrium FIRE was approaching, not another)
COUPLED_HANDOVER_MOVE = 0.1
#: "frictionless-first": Newton's state from the frictionless prediction is kept only where no node moved
#: COUPLED_PREDICTION_MOVE · min(δn, δt) or more from it (Newton polished the prediction, it did not leave it for another
#: equilibrium). Measured at 2^13 and 2^15 (ν = 0.45, seed 2, every event step): the kept states had moved 0.06–0.37
#: law lengths from the prediction; all but one were "handover-near"'s state (within 6e-7 law lengths), that one
#: another equilibrium, locally stable as FIRE's (docs/design/performance.md)
COUPLED_PREDICTION_MOVE = 1.0
#: ``coupled = "auto"`` runs "frictionless-first" where `gfmd.problem.elastic_coupling` (a half-plane's β =
#: (1 − 2ν)/(2(1 − ν))) is at most this, else "handover-near". Measured on whole coupled ramps at 2^15
#: (docs/design/solvers.md): fewer FFT pairs than "handover-near" at β ≤ 0.167 (ν ≥ 0.4), more at β ≥ 0.286
#: (ν ≤ 0.3: the Newton from the prediction rejected on most events, the tangential law moves the state more than a
#: law length from the frictionless one). Between the last win and the first loss:
COUPLED_FRICTIONLESS_COUPLING = 0.2
# Above it (the "handover-near" chain), FIRE from the frictionless prediction instead of the guess, then Newton near
# FIRE's state, was measured and dropped (docs/design/solvers.md): slightly cheaper, but many steps end on other
# branches: the prediction carries u_z through the snap without the tangential law's resistance, and the slip history
# follows it.
