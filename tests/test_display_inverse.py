"""``print(ik)`` and ``ik`` in a notebook (issue 36, text output): a summary line and a table of
the branches, their signs, actuated values and validity, instead of a dataclass dump of arrays.
Checked on the delta, whose branches at p = (0, 0, -1.2) are worked by hand (the manifest's
examples): an arm is level (theta = 0) or folded in, theta = -2 atan(8) = -2.892883 rad."""

import numpy as np

import parakin


def test_print_of_an_inverse_result_is_a_table_of_its_branches():
    m = parakin.load("delta", backend="numpy")
    text = repr(m.inverse_pose([0.0, 0.0, -1.2]))
    assert text.splitlines()[0] == "InversePose: 8 branches over the signs of (sigma1, sigma2, sigma3), 8 valid"
    folded = -2 * np.arctan(8.0)
    for line in text.splitlines()[3:]:
        branch, signs = int(line.split()[0]), line.split()[1:4]
        cells = [c for c in line.strip().split("  ") if c.strip()]
        values = [float(v) for v in cells[2].split(",")]
        expected = [0.0 if sign == "+" else folded for sign in signs]
        np.testing.assert_allclose(values, expected, atol=1e-5)
        assert cells[-1].strip() == "yes" and 0 <= branch < 8
    html = m.inverse_pose([0.0, 0.0, -1.2])._repr_html_()
    assert "<th>actuated (m, rad)</th>" in html and html.count("<tr>") == 9


def test_unreachable_branches_show_no_numbers_and_a_batch_is_summarised():
    """p = (0, 0, -2): beyond every arm's reach (the solver's numbers there are made up)."""
    m = parakin.load("delta", backend="numpy")
    text = repr(m.inverse_pose([0.0, 0.0, -2.0], strict=False))
    assert text.splitlines()[0].endswith(", 0 valid")
    for line in text.splitlines()[3:]:
        cells = [c.strip() for c in line.strip().split("  ") if c.strip()]
        assert cells[2] == "-" and cells[3] == "no: leg1_reachable, leg2_reachable, leg3_reachable"
    batch = repr(m.inverse_pose(np.array([[0.0, 0.0, -1.2], [0.0, 0.0, -2.0]]), strict=False))
    assert batch == (
        "InversePose: a batch of poses, shape (2,), 8 branches each over the signs of (sigma1, sigma2, sigma3); "
        "0 to 8 valid per pose"
    )
