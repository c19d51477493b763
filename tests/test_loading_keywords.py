"""parakin.load's own keywords get a did-you-mean (issue 36): a misspelt ``backend`` or ``limits``
is named as that keyword, not reported as an unknown parameter of the mechanism; a misspelt
parameter keeps its own suggestion."""

import pytest

import parakin


@pytest.mark.parametrize(
    ("given", "meant"),
    [("backnd", "backend"), ("Backend", "backend"), ("bakend", "backend"), ("limit", "limits"), ("limts", "limits")],
)
def test_a_misspelt_load_keyword_is_named_with_the_keyword_meant(given, meant):
    with pytest.raises(parakin.BadInputError) as error:
        parakin.load("five_bar", **{given: "numpy"})
    message = str(error.value)
    assert f"unknown keyword {given!r} of parakin.load; did you mean {meant!r}?" in message
    assert "unknown parameter" not in message
    # the parameters are listed too: the user may have meant one of them
    assert "['d', 'a1', 'a2', 'b1', 'b2']" in message


def test_a_misspelt_parameter_is_still_a_parameter():
    with pytest.raises(parakin.BadInputError, match=r"unknown parameter 'A1' for 'five_bar'; did you mean 'a1'\?"):
        parakin.load("five_bar", backend="numpy", A1=0.2)
    with pytest.raises(parakin.BadInputError, match=r"unknown parameter 'zz' for 'five_bar'; valid"):
        parakin.load("five_bar", backend="numpy", zz=0.2)


def test_the_keywords_spelt_right_load():
    m = parakin.load("five_bar", backend="numpy", limits={"theta1": (0.0, 3.0)}, d=0.2)
    assert m.backend.name == "numpy" and m.parameters["d"] == 0.2
    assert m.actuated_ranges["theta1"] == (0.0, 3.0)
