"""The classical RK4 tableau, as Exudyn's explicit RK44 integrates the bodies: what a confluence with states of its
own (SP's position, a reduced canopy's drag point) integrates them with in step with the engine's stages
(``engine.reduced``, ``methods.sp.stepping``), so that its update is the engine's to the last bit."""

RK4_STAGE_FRACTIONS = (0.0, 0.5, 0.5, 1.0)
"""a_k of the classical RK4 tableau (Exudyn's RK44): stage k's state is q_n + h a_k k_(k-1) (stage 1: q_n)."""
RK4_WEIGHTS = (1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0)
"""b_j: q_(n+1) = q_n + h sum b_j k_j, added term by term as (h b_j) k_j in Exudyn's order."""
RK4_REAL_LIMIT, RK4_IMAGINARY_LIMIT = 2.785, 2.828
"""Where RK4's stability region ends (-, h times the rate) on the negative real axis (a damped mode) and on the
imaginary axis (an undamped one); ``linearization.max_stable_step_rk4`` follows its whole boundary."""
