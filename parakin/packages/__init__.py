"""Generated packages: finding and reading them (manifest, package), the backends that evaluate
their kernels (NumPy, CasADi, compiled C) and the shared-subtree form of their symbolic models."""
