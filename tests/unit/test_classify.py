"""Classification of finished runs: at the end of `porenet run`, and `porenet classify`."""

from __future__ import annotations

import json
import math

import h5py
import pytest

import porenet
from porenet.analysis.classify import SUMMARY_KEYS, classify_run
from porenet.analysis.regimes import REGIMES
from porenet.cli.main import main
from porenet.core.errors import PluginError
from porenet.core.interfaces import Classification, Classifier
from porenet.io.runfile import read_run

IP = {"seed": 3, "lattice": {"n": 48, "disorder": 0.5}, "fluid": {"trapping": True}}


@pytest.fixture(scope="module")
def ip_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("classify") / "ip.h5"
    porenet.run(IP, output=path)
    return path


def test_run_classifies_by_default_and_writes_the_summary(ip_file):
    summary = read_run(ip_file).summary
    assert summary["regime"] in REGIMES
    assert 0 <= summary["regime_confidence"] <= 1
    assert summary["classifier"] == "rules"
    assert 1.0 < summary["fractal_dimension"] < 2.0
    assert summary["fractal_dimension_error"] > 0


def test_kind_none_builds_and_computes_nothing():
    result = porenet.run(IP | {"classifier": {"kind": "none"}})
    assert not result.plan.builds("classifier")
    assert not set(SUMMARY_KEYS) & set(result.summary)


def test_classify_command_stores_prints_and_switches_classifier(ip_file, capsys):
    assert main(["classify", str(ip_file), "--classifier", "theory", "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed["classifier"] == "theory" and printed["regime"] == "CF"
    with h5py.File(ip_file) as f:
        assert f["summary"].attrs["classifier"] == "theory"
    assert main(["classify", str(ip_file), "--no-store"]) == 0
    assert "rules" in capsys.readouterr().out
    assert read_run(ip_file).summary["classifier"] == "theory"  # --no-store left it alone
    assert main(["classify", str(ip_file)]) == 0
    assert read_run(ip_file).summary["classifier"] == "rules"


def test_classify_command_errors_name_the_problem(ip_file, tmp_path, capsys):
    assert main(["classify", str(ip_file), "--classifier", "nope"]) == 2
    assert "--classifier nope: unknown classifier kind" in capsys.readouterr().err
    missing = tmp_path / "missing.h5"
    assert main(["classify", str(missing)]) != 0
    err = capsys.readouterr().err
    assert str(missing) in err and "Traceback" not in err


class Liar(Classifier):
    def classify(self, run):
        return Classification("bubbles", 2.0)


class Refuser(Classifier):
    def classify(self, run):
        raise ValueError("pattern too small")


def test_a_classifier_outside_the_contract_is_an_error(ip_file):
    with pytest.raises(PluginError, match="'liar' returned regime 'bubbles'"):
        classify_run(read_run(ip_file), Liar(), "liar")


def test_a_classifier_that_cannot_judge_falls_back_on_theory(ip_file):
    verdict = classify_run(read_run(ip_file), Refuser(), "refuser")
    assert verdict["regime"] == "CF" and verdict["regime_confidence"] == pytest.approx(0.5)
    assert "pattern too small" in verdict["classifier_note"]
    assert math.isfinite(verdict["fractal_dimension"])


def test_a_tiny_lattice_gets_the_theory_label():
    result = porenet.run({"lattice": {"n": 3, "disorder": 0.5}, "fluid": {}})
    assert result.summary["regime"] == "CF"
    assert "fewer than" in result.summary["classifier_note"]


def test_a_pattern_without_label_or_theory_is_reported_not_classified():
    """Pressure control has no requested Ca, so no theory prediction to stand in for a
    classifier that cannot judge: the run still ends, and says why it has no regime."""
    scene = {
        "lattice": {"n": 3, "disorder": 0.3},
        "fluid": {"kind": "viscous", "control": "pressure", "injection_pressure": 1e7},
    }
    result = porenet.run(scene)
    assert result.summary["regime"] is None
    assert "not classified" in result.summary["classifier_note"]


@pytest.mark.parametrize(
    ("fluid", "solid", "expected"),
    [
        ({"trapping": True}, None, "CF"),
        ({"kind": "viscous", "capillary_number": 0.05}, None, "VF"),  # Ca* ~ 30
        ({"kind": "viscous", "capillary_number": 0.017}, {"fracturing_number": 10}, "FR"),
    ],
    ids=["invasion-percolation", "viscous", "viscous+hertz"],
)
def test_each_model_s_run_file_is_classified_as_its_regime(
    tmp_path, capsys, fluid, solid, expected
):
    """A user's run file from each model, classified from the command line (n = 60, λ = 0.1:
    deep inside each regime, docs/classification.md)."""
    scene = {"seed": 4, "lattice": {"n": 60, "disorder": 0.1}, "fluid": fluid}
    if solid is not None:
        scene["solid"] = {"kind": "hertz", **solid}
    path = tmp_path / "run.h5"
    porenet.run(scene | {"classifier": {"kind": "none"}}, output=path)
    assert main(["classify", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["regime"] == expected
    assert read_run(path).summary["regime"] == expected


class _Says(Classifier):
    """Always the given verdict (to test what classify_run does with it)."""

    def __init__(self, regime, details=None):
        self.regime, self.details = regime, details or {}

    def classify(self, run):
        return Classification(self.regime, 0.8, dict(self.details))


@pytest.mark.parametrize(
    "said, details, expected",
    [("FR/VF", {}, "VF"), ("FR/CF", {}, "CF"), ("FR", {"fingering_vote": 0.4}, "CF"),
     ("FR", {"fingering_vote": -0.4}, "VF")],
)  # fmt: skip
def test_a_rigid_medium_never_gets_a_fracturing_label(ip_file, said, details, expected):
    """Nothing can fracture in a rigid medium (straight runs of weak disorder look like
    fractures): the fingering part of the label, at half the confidence, and a note."""
    verdict = classify_run(read_run(ip_file), _Says(said, details), "stub")
    assert verdict["regime"] == expected
    assert verdict["regime_confidence"] == pytest.approx(0.4)
    assert "rigid medium" in verdict["classifier_note"]


def test_a_deformable_medium_keeps_its_fracturing_label():
    run = porenet.run(IP | {"solid": {"kind": "hertz", "fracturing_number": 1.0},
                            "classifier": {"kind": "none"}})  # fmt: skip
    verdict = classify_run(run.data, _Says("FR"), "stub")
    assert verdict["regime"] == "FR" and verdict["classifier_note"] == ""


def test_an_unmeasurable_dimension_says_why(capsys):
    """n = 3: a reason instead of "D_f = nan ± nan", printed and stored."""
    from porenet.analysis.classify import describe

    run = porenet.run(IP | {"lattice": {"n": 3, "disorder": 0.3}})
    summary = run.summary
    assert math.isnan(summary["fractal_dimension"])
    assert summary["fractal_dimension_note"].startswith("D_f not measured: ")
    line = describe(summary)
    assert "nan" not in line and "D_f not measured" in line


def test_plain_fr_without_a_vote_takes_the_theory_prediction(ip_file):
    verdict = classify_run(read_run(ip_file), _Says("FR"), "stub")
    assert verdict["regime"] == "CF"  # the theory's label for this slow, rigid scene
    assert verdict["regime_confidence"] == pytest.approx(0.4)


def test_classifying_a_run_file_needs_only_the_file(tmp_path, monkeypatch):
    """The plan's prediction is stored with the run (``plan_*`` in /summary), and the theory
    classifier reads it: classifying the file plans nothing again."""
    from porenet.io.runfile import read_run
    from porenet.kinds.theory.model import TheoryClassifier
    from porenet.simulation import Simulation

    scene = {"seed": 3, "lattice": {"n": 20, "disorder": 0.3},
             "fluid": {"kind": "viscous", "capillary_number": 1e-4}}  # fmt: skip
    path = tmp_path / "run.h5"
    Simulation.from_scene(scene, output=path).run()
    data = read_run(path)
    assert data.summary["plan_regime"] in ("CF", "VF", "CF/VF")
    assert data.summary["plan_ca_star"] > 0

    def no_planning(*args, **kwargs):
        raise AssertionError("planned again")

    monkeypatch.setattr("porenet.core.plan.make_plan", no_planning)
    verdict = TheoryClassifier().classify(data)
    assert verdict.regime == data.summary["plan_regime"]
    assert verdict.confidence == data.summary["plan_regime_confidence"]
