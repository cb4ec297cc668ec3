"""Write the reference networks of this folder with OpenPNM and PoreSpy themselves (not a
dependency of porenet: run it in a separate environment that has them).

    python -m venv /tmp/pnm && /tmp/pnm/bin/pip install openpnm porespy
    /tmp/pnm/bin/python tests/data/networks/make_reference_networks.py

* ``openpnm-cubic.npz``: OpenPNM 3's ``Cubic(shape=[8, 6, 1], spacing=1e-4)`` with the
  ``spheres_and_cylinders`` geometry collection (seed pinned), saved as
  ``numpy.savez_compressed(path, **network)``: ``throat.diameter``, ``throat.length``,
  ``throat.spacing`` (centre to centre, no ``throat.total_length``), labels ``pore.left``, ...
* ``porespy-snow2.npz``: PoreSpy's ``snow2`` network of a 48 x 48 x 32 blobs image (porosity
  0.6, voxel 2 µm, seed 1): ``throat.inscribed_diameter`` (float32), ``throat.total_length``,
  ``pore.volume``, ``pore.region_volume`` and the one label ``pore.all``.

``porenet/kinds/network/tests/test_network_lattice.py`` reads both (written with OpenPNM 3.6.4,
PoreSpy 3.2.0).
"""

from pathlib import Path

import numpy as np
import openpnm as op
import porespy as ps

HERE = Path(__file__).resolve().parent


def main() -> None:
    np.random.seed(0)  # OpenPNM's pore.seed model draws from numpy's global generator
    pn = op.network.Cubic(shape=[8, 6, 1], spacing=1e-4)
    pn.add_model_collection(op.models.collections.geometry.spheres_and_cylinders)
    pn.regenerate_models()
    np.savez_compressed(HERE / "openpnm-cubic.npz", **{k: np.asarray(v) for k, v in pn.items()})
    im = ps.generators.blobs(shape=[48, 48, 32], porosity=0.6, blobiness=1, seed=1)
    net = ps.networks.snow2(im, voxel_size=2e-6, boundary_width=0).network
    np.savez_compressed(HERE / "porespy-snow2.npz", **{k: np.asarray(v) for k, v in net.items()})
    for name in ("openpnm-cubic.npz", "porespy-snow2.npz"):
        print(f"wrote {HERE / name} ({(HERE / name).stat().st_size / 1e3:.0f} kB)")


if __name__ == "__main__":
    main()
