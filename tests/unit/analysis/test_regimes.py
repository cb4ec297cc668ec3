"""The theory predictor places scenes on the paper's phase diagrams (docs/model.md section 6)."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from porenet.analysis.regimes import REGIMES, predict_regime


@pytest.mark.parametrize(
    ("ca_star", "nf", "regime"),
    [
        (None, None, "CF"),  # quasi-static, rigid: invasion percolation
        (0.01, None, "CF"),
        (1.0, None, "CF/VF"),  # on the line Ca* = 1
        (100.0, None, "VF"),
        (100.0, 0.01, "VF"),
        (10.0, 1.0, "FR/VF"),  # on the line N_f = 1
        (0.1, 1.0, "FR/CF"),
        (10.0, 10.0, "FR"),
        (None, 10.0, "FR"),
        (10.0, math.inf, "FR"),
    ],
)
def test_regions_of_the_phase_diagram(ca_star, nf, regime):
    assert predict_regime(ca_star, nf)[0] == regime


def test_confidence_is_highest_far_from_the_lines_and_on_them():
    assert predict_regime(1e4, None)[1] > predict_regime(10.0, None)[1] > 0.5
    assert predict_regime(1.0, None)[1] == pytest.approx(1.0)
    assert predict_regime(10**0.49, None)[1] == pytest.approx(0.51, abs=0.01)


@given(
    st.one_of(st.none(), st.floats(0, 1e12)),
    st.one_of(st.none(), st.floats(0, 1e12)),
)
def test_every_input_gets_a_label_and_a_confidence(ca_star, nf):
    regime, confidence = predict_regime(ca_star, nf)
    assert regime in REGIMES
    assert 0.5 <= confidence <= 1.0


@pytest.mark.parametrize("bad", [-1.0, math.nan])
def test_bad_numbers_are_refused(bad):
    with pytest.raises(ValueError, match="ca_star"):
        predict_regime(bad, None)
