"""The ``gravity.invasion-percolation`` fluid model: invasion percolation in a gravity field.

Physics
-------
Both fluids are at rest between drainage events (quasi-static, as in porenet's
``invasion-percolation``), so each has a hydrostatic pressure. Let ``z`` be the distance from
the injection edge along gravity (here the x axis, from the inlet column towards the outlet
column), the invader lighter than the defender by ``delta_rho`` and gravity pointing along
``+z`` (the stabilising case: the light invader enters from above). Then

    P_inv(z) = P_inv(0) + rho_inv g z,        P_def(z) = P_def(0) + rho_def g z.

The meniscus in throat ``t`` (aperture ``r_t``, at height ``z_t``) advances once the local
capillary pressure reaches its entry pressure, ``P_inv(z_t) - P_def(z_t) >= 2 gamma / r_t``,
that is once the capillary pressure *at the injection edge*,
``p = P_inv(0) - P_def(0)``, the one control variable shared by every meniscus, reaches

    p_t = 2 gamma / r_t + delta_rho g z_t.

Dividing by porenet's pressure scale ``gamma / a`` gives the scaled threshold

    p_t / (gamma / a) = 2 / (r_t / a) + Bo (z_t / a),     Bo = delta_rho g a^2 / gamma,

where ``r_t / a`` is the scaled aperture in ``state.apertures`` and ``z_t / a`` the scaled
height. The quasi-static invasion raises ``p`` just enough at each step to drain the pore
behind the frontier throat of smallest ``p_t``: invasion percolation with the threshold field
``p_t`` instead of ``2 / r_t`` (Wilkinson 1984 [1]_). The destabilising orientation (light
invader from below) changes the sign of the hydrostatic term. ``z_t`` is the height of the
throat's midpoint (the mean of its two pores' x coordinates) above the inlet pores' x.

The invasion is computed once, at :meth:`GravityInvasionPercolation.setup`, by porenet's public
kernel :func:`porenet.kinds.invasion.kernels.invasion_sequence` (with trapping when configured) and
replayed by :meth:`~GravityInvasionPercolation.advance` in the chunks the Simulation asks for,
exactly as porenet's own ``invasion-percolation`` does; with ``Bo = 0`` the two are the same
model and give the same drainage order.

With a stabilising field the front settles to a statistically steady width ``w`` that scales
like ``Bo^(-nu / (1 + nu))`` with the percolation correlation-length exponent ``nu = 4/3`` in
two dimensions ([1]_, [2]_, [3]_); :mod:`porenet_gravity.front` measures it.

References
----------
.. [1] D. Wilkinson, "Percolation model of immiscible displacement in the presence of buoyancy
   forces", Phys. Rev. A 30, 520-531 (1984).
.. [2] A. Birovljev, L. Furuberg, J. Feder, T. Jøssang, K. J. Måløy and A. Aharony, "Gravity
   invasion percolation in two dimensions: experiment and simulation", Phys. Rev. Lett. 67,
   584-587 (1991).
.. [3] B. Sapoval, M. Rosso and J.-F. Gouyet, "The fractal nature of a diffusion front and the
   relation to percolation", J. Physique Lett. 46, L149-L156 (1985).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from porenet.core.errors import ConfigError
from porenet.core.interfaces import FluidModel, Lattice, RunContext
from porenet.core.state import State
from porenet.kinds.invasion.kernels import enclosed_defender, entry_pressures, invasion_sequence
from porenet_gravity.config import KIND, GravityInvasionConfig
from porenet_gravity.front import INJECTION, front_statistics, throat_heights

__all__ = ["GravityInvasionPercolation", "invasion_thresholds"]


def invasion_thresholds(
    apertures: np.ndarray, heights: np.ndarray, bond_number: float, sign: float = 1.0
) -> np.ndarray:
    """Invasion thresholds ``p_t = 2 / r_t + sign * Bo * z_t`` in units of ``gamma / a``.

    Parameters
    ----------
    apertures : numpy.ndarray, shape (M,)
        Throat apertures ``r_t / a`` (positive), in the lattice's canonical throat order.
    heights : numpy.ndarray, shape (M,)
        Throat heights ``z_t / a`` along gravity, measured from the injection edge
        (:func:`porenet_gravity.front.throat_heights`).
    bond_number : float
        ``Bo = delta_rho g a^2 / gamma`` (-), ``>= 0``.
    sign : float
        +1 (stabilising) or -1 (destabilising).

    Returns
    -------
    numpy.ndarray, shape (M,)
        Capillary entry pressure plus hydrostatic term (scaled by ``gamma / a``). For
        ``bond_number == 0`` it is exactly porenet's
        :func:`porenet.kinds.invasion.kernels.entry_pressures`, so the invasion is porenet's own.

    References
    ----------
    D. Wilkinson, Phys. Rev. A 30, 520 (1984), Eq. (2.1) in the notation of this module.
    """
    entry = entry_pressures(apertures)
    if bond_number == 0:
        return entry
    return entry + (sign * bond_number) * np.asarray(heights, dtype=np.float64)


class GravityInvasionPercolation(FluidModel):
    """Invasion percolation in a gravity field along x, from the left edge (kind
    ``gravity.invasion-percolation``).

    Reads ``state.apertures`` once, at :meth:`setup`. Writes, as porenet's FluidModel contract
    asks: ``drained`` (inlets at the first :meth:`advance`, then each replayed step),
    ``record`` (pore, throat, threshold ``p_t`` in ``gamma / a``, time 0; inlets with throat
    -1 and pressure 0), ``n_drained``, ``invading_pressure`` (the last step's threshold: the
    capillary pressure at the injection edge, ``gamma / a``), ``breakthrough``, ``step``
    (once per :meth:`advance`), and ``trapped`` at :meth:`finalize`. ``pressure`` stays None
    (no pressure field) and ``time`` stays 0 (quasi-static).

    Parameters
    ----------
    config : GravityInvasionConfig
        The validated ``[fluid]`` section.
    lattice : porenet.core.interfaces.Lattice
        Any lattice: only ``pore_coords``, ``throat_pores``, ``adjacency``, ``inlet_pores``
        and ``outlet_mask`` are used.
    context : porenet.core.interfaces.RunContext
        Must have ``injection.at == "left-edge"`` and a rigid medium.

    Raises
    ------
    porenet.core.errors.ConfigError
        For another injection site (gravity is defined relative to the injection edge) or a
        deformable solid (the thresholds are computed once from the initial apertures).
    """

    solves_pressure = False
    config: GravityInvasionConfig

    def __init__(
        self, config: GravityInvasionConfig, lattice: Lattice, context: RunContext
    ) -> None:
        super().__init__(config, lattice, context)
        at = getattr(context.injection, "at", None)
        if at != INJECTION:
            raise ConfigError(
                f"fluid.kind {KIND!r} needs [injection] at = {INJECTION!r} (gravity acts along "
                f"x, from the injection edge to the outlet), got at = {at!r}"
            )
        if context.deformable:
            raise ConfigError(
                f"fluid.kind {KIND!r} supports rigid media only (its thresholds are computed "
                "once from the initial apertures); use [solid] kind = 'rigid'"
            )

    def setup(self, state: State) -> None:
        """Compute the thresholds and the whole invasion sequence (nothing drained yet)."""
        lat, cfg, stop = self.lattice, self.config, self.context.stop
        self.heights = throat_heights(lat.pore_coords, lat.throat_pores, lat.inlet_pores(INJECTION))
        self.thresholds = invasion_thresholds(
            state.apertures, self.heights, cfg.bond_number, cfg.sign
        )
        self.outlet = np.asarray(lat.outlet_mask(INJECTION), dtype=bool)
        max_steps = lat.n_pores if stop.max_drained is None else int(stop.max_drained)
        order, via = invasion_sequence(
            lat.adjacency,
            self.thresholds,
            lat.inlet_pores(INJECTION),
            self.outlet,
            trapping=cfg.trapping,
            stop_at_outlet=stop.at == "breakthrough",
            max_steps=max_steps,
        )
        self.order = order
        self.via = via
        self.step_pressure = np.where(via >= 0, self.thresholds[np.maximum(via, 0)], 0.0)
        self.cursor = 0

    def advance(self, state: State, max_events: int) -> int:
        """Replay the next ``max_events`` steps of the precomputed sequence into the State."""
        start = self.cursor
        stop = min(len(self.order), start + max(int(max_events), 0))
        if stop <= start:
            return 0
        pores = self.order[start:stop]
        state.drained[pores] = True
        state.record.extend(
            pores, self.via[start:stop], self.step_pressure[start:stop], np.zeros(stop - start)
        )
        state.n_drained += stop - start
        state.invading_pressure = float(self.step_pressure[stop - 1])
        if not state.breakthrough and bool(self.outlet[pores].any()):
            state.breakthrough = True
        state.step += 1
        self.cursor = stop
        return stop - start

    @property
    def exhausted(self) -> bool:
        """True once the whole precomputed sequence has been replayed."""
        return self.cursor >= len(self.order)

    def finalize(self, state: State) -> None:
        """Mark the defending pores cut off from the outlet as trapped."""
        indptr, neighbours, _ = self.lattice.adjacency
        state.trapped[:] = enclosed_defender(indptr, neighbours, state.drained, self.outlet)

    def summary(self, state: State) -> dict[str, Any]:
        """Scalar results in SI for the run file's ``/summary``.

        Returns
        -------
        dict
            ``bond_number`` (-); ``hydrostatic_gradient`` ``|delta_rho| g = Bo gamma / a^2``
            (Pa/m); ``max_entry_pressure``, the largest threshold overcome, i.e. the highest
            capillary pressure at the injection edge (Pa); ``front_position`` and
            ``front_width``, the mean and standard deviation of the height of the final front
            (m, :func:`porenet_gravity.front.front_statistics`; None when there is no front);
            ``front_pores``, the number of pores on it.
        """
        scales = self.context.scales
        size = state.record.size
        steps = state.record.throat[:size] >= 0
        p = state.record.pressure[:size][steps]
        position, width, count = front_statistics(self.lattice, state.drained, self.outlet)
        return {
            "bond_number": float(self.config.bond_number),
            "hydrostatic_gradient": self.config.bond_number * scales.pressure / scales.length,
            "max_entry_pressure": float(p.max()) * scales.pressure if p.size else 0.0,
            "front_position": None if count == 0 else position * scales.length,
            "front_width": None if count == 0 else width * scales.length,
            "front_pores": count,
        }
