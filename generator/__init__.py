"""parakin generator: the symbolic pipeline (SymPy) that turns mechanism definitions into code.

Stages, each a module with one job:
    frames      homogeneous transforms, Craig's modified DH links, Z-Y-X Euler angles
    model       the declarative mechanism model that ``mechanisms/*`` fill in
    chains      serial-chain legs (modified-DH tables): the inverse by decomposition, factors, drawing
    trigpoly    factoring of trigonometric polynomials modulo sin^2 + cos^2 = 1
    derive      Jacobians, determinants and named singularity factors
    configurations  regular configurations near the home and the examples: the factor checks'
                samples and the C example's input
    program     straight-line programs with common-subexpression elimination
    emit        rendering of programs through the Jinja templates (NumPy, CasADi, C, SymPy)
    build       the atomic ``make generate`` driver

Never imported at run time: ``parakin`` loads only what this package writes into ``generated/``.
"""
