"""Comparison harness: OpenPNM 3.6.4 invasion percolation on porenet's square lattice.

This module is importable without OpenPNM; ``openpnm`` is imported lazily.

Canonical (porenet) layout for an ``n x n`` lattice
---------------------------------------------------
* pore ``(i, j)`` (row ``i``, column ``j``) has index ``i*n + j``;
* throats ``0 .. n*(n-1)-1``: horizontal ``(i,j)-(i,j+1)``, index ``i*(n-1) + j``;
* throats ``n*(n-1) .. 2*n*(n-1)-1``: vertical ``(i,j)-(i+1,j)``,
  index ``n*(n-1) + i*n + j``;
* entry pressure ``p_e = 2*gamma/r``; the inlet is the centre pore ``(n//2, n//2)``;
  the outlets (for trapping) are all pores on the outer edge.

What OpenPNM 3.6.4 actually does (read from
``openpnm/algorithms/_invasion_percolation.py``)
--------------------------------------------------------------------------
* ``run()`` always invades the whole network (``n_steps = inf``), popping throats
  from a heap keyed by their rank in ``np.argsort(entry_pressure)``.  The
  counter behind ``pore.invasion_sequence`` is incremented per *throat* popped
  (including throats joining two already-invaded pores), so pore sequence values
  are unique but not contiguous; the inlet has 0.  Ties in entry pressure are
  broken by the (unstable, quicksort) argsort rank, not by insertion time.
* ``pore.invasion_pressure`` is the entry pressure of the throat through which
  the pore was invaded (0 for the inlet), *not* the running maximum.
* Trapping is *post hoc*: ``run()`` ignores trapping, ``apply_trapping()`` then
  runs Masson's reverse union-find.  It sets
  ``pore.invasion_sequence[outlets] = max + 1`` **in place** (outlets are
  treated as never invaded), marks trapped pores in ``pore.trapped``, and
  converts ``pore/throat.invasion_sequence`` to float with trapped entries =
  ``inf``.  Throats that did not invade a pore (and throats into outlets, due
  to the in-place overwrite) get ``throat.trapped = True`` / ``inf``.
  Because of the overwrite we copy the sequence right after ``run()``.
* Because outlets are always counted as "defending", a defending cluster with
  no edge pore of its own still escapes if it touches an *already invaded*
  edge pore.  That is weaker than porenet's rule (a cluster is trapped once
  none of *its* pores is on the edge).  ``outlet_ring=True`` reproduces
  porenet's rule exactly: the lattice is embedded in an ``(n+2) x (n+2)``
  Cubic whose outer ring pores are the outlets and whose ring throats have
  infinite entry pressure, so the ring is only invaded after every real pore.
"""

from __future__ import annotations

import contextlib
import time

import numpy as np

__all__ = ["canonical_throat_conns", "openpnm_available", "openpnm_invasion"]

_WARMUP_SECONDS: float | None = None


def openpnm_available() -> bool:
    """True if ``import openpnm`` works in this interpreter."""
    try:
        import openpnm  # noqa: F401
    except Exception:  # ImportError, or a broken numba/scipy stack
        return False
    return True


def canonical_throat_conns(n: int) -> np.ndarray:
    """(2*n*(n-1), 2) int64 array of porenet's canonical throat -> pore pairs."""
    i, j = np.meshgrid(np.arange(n), np.arange(n - 1), indexing="ij")
    h = np.stack([i * n + j, i * n + j + 1], axis=-1).reshape(-1, 2)
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n), indexing="ij")
    v = np.stack([i * n + j, (i + 1) * n + j], axis=-1).reshape(-1, 2)
    return np.concatenate([h, v]).astype(np.int64)


def _build(n: int, pe_ours: np.ndarray, outlet_ring: bool):
    """Build the OpenPNM network, phase and maps. Returns a namespace dict."""
    import openpnm as op

    m = n + 2 if outlet_ring else n
    off = 1 if outlet_ring else 0
    spacing = 1.0
    pn = op.network.Cubic(shape=[m, m, 1], spacing=spacing)
    Np_op, Nt_op = pn.Np, pn.Nt

    # --- pore map by coordinates: OpenPNM x <-> our row i, y <-> our column j.
    xy = np.rint(pn["pore.coords"][:, :2] / spacing - 0.5).astype(np.int64)
    assert xy.min() == 0 and xy.max() == m - 1
    assert np.allclose(pn["pore.coords"][:, 2], 0.5 * spacing)
    gi, gj = xy[:, 0] - off, xy[:, 1] - off
    real = (gi >= 0) & (gi < n) & (gj >= 0) & (gj < n)
    assert real.sum() == n * n
    op2ours = np.full(Np_op, -1, dtype=np.int64)
    op2ours[real] = gi[real] * n + gj[real]
    ours2op = np.full(n * n, -1, dtype=np.int64)
    ours2op[op2ours[real]] = np.flatnonzero(real)
    assert (ours2op >= 0).all() and (op2ours[ours2op] == np.arange(n * n)).all()

    # --- throat map by matching the (sorted) pore pairs, expressed in our ids.
    conns_op = np.asarray(pn["throat.conns"], dtype=np.int64)
    ours_conns = canonical_throat_conns(n)
    N = n * n
    a, b = op2ours[conns_op[:, 0]], op2ours[conns_op[:, 1]]
    t_real = (a >= 0) & (b >= 0)
    key_op = np.where(t_real, np.minimum(a, b) * N + np.maximum(a, b), -1)
    key_ours = ours_conns.min(axis=1) * N + ours_conns.max(axis=1)
    assert t_real.sum() == len(key_ours) == 2 * n * (n - 1)
    srt = np.argsort(key_op)
    pos = np.searchsorted(key_op, key_ours, sorter=srt)
    ours2op_t = srt[pos]
    assert (key_op[ours2op_t] == key_ours).all(), "throat mapping failed"
    assert len(np.unique(ours2op_t)) == len(ours2op_t)
    # Independent check: OpenPNM's conns of the mapped throats, translated back to
    # our pore ids, equal our canonical conns (as unordered pairs).
    back = np.sort(op2ours[conns_op[ours2op_t]], axis=1)
    assert (back == np.sort(ours_conns, axis=1)).all()

    pe_op = np.full(Nt_op, np.inf)  # ring throats (outlet_ring only): never before real ones
    pe_op[ours2op_t] = pe_ours
    assert np.isfinite(pe_op[t_real]).all()

    if outlet_ring:
        outlets = np.flatnonzero(~real)
    else:
        edge = (gi == 0) | (gi == n - 1) | (gj == 0) | (gj == n - 1)
        outlets = np.flatnonzero(edge)
        assert (np.asarray(pn["pore.surface"])[outlets]).all()
        assert np.asarray(pn["pore.surface"]).sum() == len(outlets)

    phase = op.phase.Phase(network=pn)
    phase["throat.entry_pressure"] = pe_op
    inlet = ours2op[(n // 2) * n + n // 2]
    # OpenPNM refuses a pore that is both inlet and outlet (only happens for n <= 2).
    outlets = outlets[outlets != inlet]
    return dict(
        op=op,
        pn=pn,
        phase=phase,
        op2ours=op2ours,
        ours2op=ours2op,
        inlet=inlet,
        outlets=outlets,
        real=real,
    )


def _run(ctx, trapping: bool):
    """Run IP (+ trapping). Returns (seq_after_run, pore_pressure, trapped, seconds)."""
    op, pn, phase = ctx["op"], ctx["pn"], ctx["phase"]
    ip = op.algorithms.InvasionPercolation(network=pn, phase=phase)
    ip.set_inlet_BC(pores=[ctx["inlet"]])
    if trapping:
        ip.set_outlet_BC(pores=ctx["outlets"])
    t0 = time.perf_counter()
    ip.run()
    t1 = time.perf_counter()
    # apply_trapping overwrites outlet sequences in place -> keep a copy.
    seq = np.array(ip["pore.invasion_sequence"], dtype=np.int64, copy=True)
    pres = np.array(ip["pore.invasion_pressure"], dtype=float, copy=True)
    t2 = time.perf_counter()
    if trapping:
        ip.apply_trapping()
    t3 = time.perf_counter()
    trapped = np.array(ip["pore.trapped"], dtype=bool, copy=True)
    if trapping:  # sanity: trapped <=> sequence set to inf by apply_trapping
        assert (np.isinf(ip["pore.invasion_sequence"]) == trapped).all()
    return seq, pres, trapped, (t1 - t0) + (t3 - t2)


def _close(ctx):
    with contextlib.suppress(Exception):
        ctx["op"].Workspace().close_project(ctx["pn"].project)


def _warmup() -> float:
    """Compile OpenPNM's numba kernels once (small net, with trapping)."""
    global _WARMUP_SECONDS
    if _WARMUP_SECONDS is None:
        t0 = time.perf_counter()
        n = 7
        rng = np.random.default_rng(12345)
        pe = 2.0 / rng.uniform(0.7, 1.3, 2 * n * (n - 1))
        for ring in (False, True):
            ctx = _build(n, pe, ring)
            _run(ctx, trapping=True)
            _close(ctx)
        _WARMUP_SECONDS = time.perf_counter() - t0
    return _WARMUP_SECONDS


def openpnm_invasion(
    apertures: np.ndarray,
    n: int,
    trapping: bool,
    interfacial_tension: float = 1.0,
    pore_size: float = 1.0,
    *,
    outlet_ring: bool = False,
) -> dict:
    """Run OpenPNM's InvasionPercolation on porenet's n x n lattice.

    ``pore_size`` is accepted for signature compatibility; IP order does not
    depend on it (OpenPNM only uses volumes in ``pc_curve``).

    Returns a dict with ``order`` (our pore ids in invasion order, inlet first,
    trapped pores excluded), ``trapped`` (bool, our pore ids), ``pressure``
    (entry pressure of the throat that invaded each pore of ``order``, 0 for the
    inlet), ``seconds_run`` (run + apply_trapping), ``seconds_warmup``,
    ``openpnm_version``, plus ``sequence`` (OpenPNM's raw pore sequence after
    ``run()``, in our pore ids).
    """
    import openpnm as op

    n = int(n)
    if n < 2:
        raise ValueError("n must be >= 2")
    r = np.asarray(apertures, dtype=float).ravel()
    if r.shape != (2 * n * (n - 1),):
        raise ValueError(f"apertures must have length 2*n*(n-1) = {2 * n * (n - 1)}")
    if not (np.all(np.isfinite(r)) and np.all(r > 0)):
        raise ValueError("apertures must be finite and > 0")
    pe_ours = 2.0 * float(interfacial_tension) / r

    warm = _warmup()
    ctx = _build(n, pe_ours, bool(outlet_ring))
    try:
        seq_op, pres_op, trapped_op, secs = _run(ctx, bool(trapping))
    finally:
        _close(ctx)

    ours2op = ctx["ours2op"]
    seq = seq_op[ours2op]  # indexed by our pore id
    pres = pres_op[ours2op]
    trapped = trapped_op[ours2op] if trapping else np.zeros(n * n, dtype=bool)
    assert (seq >= 0).all(), "OpenPNM left real pores uninvaded"
    assert len(np.unique(seq)) == n * n
    keep = np.flatnonzero(~trapped)
    order = keep[np.argsort(seq[keep], kind="stable")].astype(np.int64)
    assert order[0] == (n // 2) * n + n // 2
    return {
        "order": order,
        "trapped": trapped,
        "pressure": pres[order].astype(float),
        "seconds_run": float(secs),
        "seconds_warmup": float(warm),
        "openpnm_version": op.__version__,
        "sequence": seq,
    }


def _main() -> None:
    import argparse
    import statistics

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=400)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument(
        "--outlet-ring",
        action="store_true",
        help="emulate porenet's edge-cluster trapping rule exactly",
    )
    args = ap.parse_args()
    if not openpnm_available():
        raise SystemExit("openpnm is not importable")
    n = args.n
    rng = np.random.default_rng(0)
    apertures = rng.uniform(0.7, 1.3, 2 * n * (n - 1))
    for trapping in (False, True):
        times, res = [], None
        for _ in range(args.repeats):
            res = openpnm_invasion(apertures, n, trapping, outlet_ring=args.outlet_ring)
            times.append(res["seconds_run"])
        print(
            f"openpnm {res['openpnm_version']}  n={n}  trapping={trapping}  "
            f"outlet_ring={args.outlet_ring}"
        )
        print(
            f"  warm-up (JIT) {res['seconds_warmup']:.3f} s; run+trapping median "
            f"{statistics.median(times):.3f} s  (runs: "
            + ", ".join(f"{t:.3f}" for t in times)
            + ")"
        )
        print(f"  invaded {len(res['order'])} / {n * n}, trapped {int(res['trapped'].sum())}")
        print(f"  first 20: {res['order'][:20].tolist()}")


if __name__ == "__main__":
    _main()
