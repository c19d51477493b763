"""What a certificate proves, and what it does not, within rounding of a fold (issue 31).

Proven: a homotopy's certificate is about the system whose coefficients are the input's as
computed in double precision (the generated family kernel at the input, rounded): each listed
mode is a real root of that system alone in its box, distinct modes in disjoint boxes, and
"complete" says that no root of that system is missing (its root count reached by distinct
certified roots).

Not proven: the modes of the exact input. The rounded coefficients differ from the exact ones by
~1e-15 relative, so within about that of a fold of the forward map (two real modes meeting) the
rounded system can have two real modes more or fewer than the exact input. The adversarial
census (tests/test_certificate_adversarial.py) therefore holds certificates to the exact count
only where the oracle's count does not change within 1e-12 of the input (``Family.stable``).

The input below is the adversarial corpus's planar_3rrr geometry seed 5, its fold stepped off by
0 (to the float on the side with k modes): the exact oracle (rational arithmetic, 60 digits)
counts 2 real modes and does not decide the same count 1e-12 away; the certificate is complete
with 4 modes, each checked here to be a real root of the rounded system by the exact
certifier, in pairwise disjoint boxes.
"""

from __future__ import annotations

import numpy as np
import oracle_modes as om

import parakin
from parakin.solvers import modes as modes_module
from parakin.solvers.exact_certify import certify_root_exactly

AT_FOLD = ("planar_3rrr", 5, ("-0x1.041a1065d3419p-1", "0x1.adc7b051a76fap+0", "-0x1.0d7022fcb6292p-3"))


def test_a_certificate_proves_the_rounded_system_not_the_exact_input_at_a_fold():
    name, seed, hexes = AT_FOLD
    family = om.family(name)
    parameters = family.geometry(seed)
    values = np.array([float.fromhex(h) for h in hexes])
    oracle = om.cached(name, parameters, values)
    assert oracle.usable and oracle.count == 2  # the exact input: 2 real modes
    assert not family.stable(parameters, values)  # ... and 4 within 1e-12 of it
    m = parakin.load(name, backend="numpy", **family.load_arguments(parameters))
    info = m.capabilities.forward_methods[family.method]
    out = m._every_mode(info, values[None], True)
    modes = modes_module.assemble(m, values[None], out, info)
    certificate = modes.certificate()
    assert bool(certificate["complete"][0]) and int(modes.count[0]) == 4
    # the rounded system, as the certificate sees it (the geometry in its own size)
    scaled, _ = m._unit_free or (m, 1.0)
    free, angles = modes_module._family(scaled, info, values[None])
    coefficients = modes_module._target_coefficients(scaled, info, free, angles)[0]
    homotopy = info.homotopy
    z = out["endpoints"][0, ..., 0] + 1j * out["endpoints"][0, ..., 1]
    boxes = []
    for slot in np.nonzero(modes.valid[0])[0]:
        box = certify_root_exactly(coefficients, homotopy.exponents, homotopy.equation, z[slot], True)
        assert box.unique and box.real == 1  # a real root of the rounded system, alone in its box
        boxes.append(box)
    centres = np.array([box.center for box in boxes])
    radii = np.array([box.radius for box in boxes])
    apart = np.abs(centres[:, None] - centres[None]).max(-1) > radii[:, None] + radii[None]
    assert len(boxes) == 4 and apart[~np.eye(4, dtype=bool)].all()  # 4 distinct real roots of it
