"""The scenes of the regression suite: every fluid model, integrator, control, meniscus rule,
solid option and coupling schedule, each on a lattice small enough to run in about a second.

``python tests/regression/generate.py`` runs them and stores their outcomes in
``tests/regression/outcomes/`` with ``provenance.json`` (the commit, the date, the versions);
``tests/regression/test_regression.py`` runs them again and compares.
"""

from __future__ import annotations

from typing import Any


def _scene(fluid: dict[str, Any], n: int = 24, seed: int = 5, **sections: Any) -> dict[str, Any]:
    out: dict[str, Any] = {
        "seed": seed,
        "lattice": {"kind": "square", "n": n, "disorder": 0.3, "pore_size": 1e-7},
        "fluid": fluid,
        "stop": {"at": "breakthrough"},
        "classifier": {"kind": "none"},
    }
    out.update(sections)
    return out


IP = {"kind": "invasion-percolation"}
VISCOUS = {"kind": "viscous", "capillary_number": 1e-4}
HERTZ = {"kind": "hertz", "fracturing_number": 1.0}

#: name -> scene (a dict as a TOML file would give)
SCENES: dict[str, dict[str, Any]] = {
    "ip-trapping": _scene(IP, n=60),
    "ip-no-trapping-complete": _scene(IP | {"trapping": False}, n=40, stop={"at": "complete"}),
    "ip-left-edge": _scene(IP, n=40, injection={"at": "left-edge"}),
    "viscous-explicit": _scene(VISCOUS | {"integrator": "explicit"}),
    "viscous-explicit-latching": _scene(
        VISCOUS | {"integrator": "explicit", "meniscus": "latching"}
    ),
    "viscous-explicit-pressure-step": _scene(
        VISCOUS | {"integrator": "explicit", "capillary_number": 1e-2, "pressure_step": 0.1}
    ),
    "viscous-rkc": _scene(VISCOUS | {"integrator": "rkc", "local_steps": "off"}, n=30),
    "viscous-rkc-latching-drained-reservoir": _scene(
        VISCOUS | {"integrator": "rkc", "meniscus": "latching", "reservoir": "drained"}
    ),
    "viscous-rkc-local-steps": _scene(
        VISCOUS | {"integrator": "rkc", "local_steps": "on", "capillary_number": 1e-5}, n=40
    ),
    "viscous-implicit": _scene(VISCOUS | {"integrator": "implicit"}, n=16),
    "viscous-pressure-control": _scene(
        VISCOUS
        | {
            "control": "pressure",
            "capillary_number": None,
            "injection_pressure": 1.6e6,
            "max_time": 2e-6,
            "snapshot_saturations": [0.05],
            "snapshot_times": [1e-6],
        }
    ),
    "viscous-ramp": _scene(
        VISCOUS
        | {
            "control": "ramp",
            "capillary_number": None,
            "ramp_rate": 1e12,
            "injection_pressure": 1.0e6,
            "max_time": 2e-6,
        }
    ),
    "viscous-complete": _scene(VISCOUS | {"integrator": "explicit"}, n=12, stop={"at": "complete"}),
    "viscous-hertz": _scene(VISCOUS, solid=HERTZ),
    "viscous-hertz-soft-interval": _scene(
        VISCOUS, solid=HERTZ | {"fracturing_number": 10.0, "coupling": "interval"}
    ),
    "ip-hertz": _scene(IP, n=30, solid=HERTZ),
    "ip-hertz-soft-sparse": _scene(
        IP, n=24, solid=HERTZ | {"fracturing_number": 10.0, "solver": "sparse-direct"}
    ),
    "ip-hertz-foundation-never": _scene(
        IP,
        n=24,
        solid=HERTZ | {"fracturing_number": 10.0, "foundation": 0.05, "recontact": "never"},
    ),
}
