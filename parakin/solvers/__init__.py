"""The solvers behind a Mechanism's methods: every assembly mode (polynomial roots, homotopy
continuation, their certificates), tracking, self-motion continuation, statics, the one pivoted
solve, and the interface of a loaded mechanism they read (``loaded.LoadedMechanism``)."""
