"""Macro steps of local time stepping for the viscous model's RKC integrator.

The scheme and its kernels are in :mod:`porenet.kinds.viscous.kernels.multirate` and
:mod:`porenet.kinds.viscous.kernels.window`; this class decides, before each macro step, its length
``H`` and its window, and books the far field after it. Decisions (measured in docs/performance.md
and docs/accuracy.md):

* **Where the window goes**: a box around the *hot* pores (pores drained, and pores entered
  by menisci that moved, within the last :attr:`LocalSteps.memory` macro-step lengths, plus
  the pores of the menisci now at their threshold), widened to hold every pore whose error
  estimate in the coarse step exceeds ``window_tolerance`` times the tolerance (with
  :attr:`LocalSteps.error_margin` pores to spare), and by at least ``kappa sqrt(H rho)``
  pores (``sqrt(H rho)`` is, to a factor, the distance in pores the pressure diffuses in
  ``H``; ``rho`` the spectral radius), clipped to the active box. A macro step ends early
  when a pore drains within half the hot pores' distance to an open edge of the window, or
  when a meniscus outside it reaches its threshold; the next one is centred again.
* **The coarse step's menisci**: the injection rate Q as a constant source, shared among the
  pores of the menisci at their threshold (or given to the one nearest to it).
* **How long**: at most twice the last ``H`` and what the refluxed volumes allow (the
  coarse step's blind spot, kept below half the tolerance as a pressure change; they grow
  like ``H^2``, and ``kappa`` grows with them), and within that the length that minimises
  the predicted pore updates per unit time: the coarse stages over the active box per ``H``
  plus the fine sweeps per unit time (learnt) over a window whose reach grows like
  ``sqrt(H)`` (learnt).
* **When there is none**: single-rate RKC drains the next pore when the active box is below
  :attr:`LocalSteps.min_box` pores (``local_steps = "auto"``), when no window within
  :attr:`LocalSteps.max_share` of the active box holds the coarse step's errors, or when a
  macro step is predicted to cost more than :attr:`LocalSteps.gain` times single-rate steps.

Length (over the ~500 lines of docs/architecture.md's rule): one class, the decisions of local
time stepping (window, macro-step length, far field, when to fall back to global steps), each
documented above with its measurement; the kernels it drives are already apart (multirate.py,
window.py).
"""

from __future__ import annotations

import math
from typing import Any, Protocol

import numpy as np

from porenet.core.errors import NumericalError
from porenet.kinds.viscous.kernels import multirate
from porenet.kinds.viscous.kernels.chebyshev import MAX_STAGES, longest_step, stage_count
from porenet.kinds.viscous.kernels.diffusion import grow_where_reached
from porenet.kinds.viscous.kernels.state import (
    Column,
    Conductances,
    Count,
    Flow,
    Front,
    Menisci,
    Network,
    Pump,
    Records,
    Status,
    Sweep,
    Total,
)
from porenet.kinds.viscous.kernels.window import (
    Cut,
    Mode,
    Ring,
    Window,
    WindowFloat,
    WindowInt,
    window_arrays,
)
from porenet.kinds.viscous.kernels.window import box_area as _area

#: Candidate windows of a coarse step: their reach beyond the hot pores, as multiples of the
#: reach the last coarse steps needed.
LEVELS = (0.6, 0.8, 1.0, 1.25, 1.6, 2.0)

#: Counters reported in ``/summary``.
STATS = ("macro_steps", "macro_cuts", "single_rate_pores", "single_rate_sweeps",
         "coarse_stage_sweeps", "coarse_rejected_steps", "window_pore_stages",
         "coarse_pore_stages")  # fmt: skip


class RkcModel(Protocol):
    """What :class:`LocalSteps` uses of the viscous model it steps (implemented by
    :class:`porenet.kinds.viscous.model.ViscousDrainage`): the kernels' named state
    (:mod:`porenet.kinds.viscous.kernels.state`), a few numbers, and four methods. Nothing else."""

    config: Any  #: the fluid's config (tolerance, pressure_floor, max_steps, meniscus)
    network: Network
    conductances: Conductances
    flow: Flow
    front: Front
    records: Records
    rkc: Any  #: :class:`porenet.kinds.viscous.kernels.rkc.Rkc` (buffers F_E, stages, zeros)
    pressure_scale: float  #: the unit of the tolerance (gamma / a)

    @property
    def injection_rate(self) -> float: ...

    @property
    def spectral_radius(self) -> float: ...

    def rkc_steps(
        self,
        budget: int,
        t_end: float,
        step_budget: int | None = None,
        window: Window | None = None,
        window_front: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
    ) -> int: ...

    def rates_changed(self) -> None: ...

    def no_menisci(self) -> tuple[Menisci, Pump]: ...

    def rkc_sweeps(self) -> float: ...


class LocalSteps:
    """Local time stepping for a viscous model (an :class:`RkcModel`) run with the RKC
    integrator on a square grid under rate control."""

    #: Largest share of the active box a window may cover before ``H`` is halved.
    max_share = 0.5
    #: Hot pores stay hot for this many macro-step lengths.
    memory = 3.0
    #: Pores of the window around the hot pores, at least, and around the coarse step's
    #: pores over the window tolerance.
    hot_margin = 8
    error_margin = 2
    #: Refluxed pressure change allowed, as a fraction of the tolerance.
    reflux_fraction = 0.5
    #: Fewest stages of a coarse step worth taking (below, a single-rate step instead).
    min_stages = 6
    #: Coarse steps tried for one macro step before a single-rate step is taken instead.
    max_attempts = 8
    #: A macro step is taken only if its predicted cost is below this fraction of the
    #: single-rate steps' (:meth:`_plan`), and only on an active box of at least
    #: :attr:`min_box` pores (at n = 100, Ca = 1e-5 the macro steps' fixed costs made the
    #: run 12 % slower than single-rate steps; at n = 200 they made it 1.4x faster).
    gain = 0.8
    min_box = 40_000

    def __init__(self, fluid: RkcModel, window_tolerance: float, always: bool = False) -> None:
        self.fluid = fluid
        self.window_tolerance = window_tolerance
        #: ``local_steps = "on"``: macro steps on active boxes of any size (where the cost
        #: model predicts a gain).
        self.always = always
        n = fluid.network.grid_n
        self.n = n
        n_pores = n * n
        n_throats = len(fluid.conductances.area)
        self.win = window_arrays(Mode.FINE, 4 * n * (len(LEVELS) + 1), n_pores, n_throats)
        #: The window's own front (its menisci) and their slots, and counters, for the fine
        #: integration (:func:`porenet.kinds.viscous.kernels.multirate.split_front`).
        self._wfront = np.zeros(n_throats, dtype=np.int64)
        self._wfpos = np.full(n_throats, -1, dtype=np.int64)
        self._p1 = np.zeros(n_pores)
        self._scratch = np.zeros(n_pores)
        self._ebox = np.zeros(4, dtype=np.int64)
        self._hot_time: list[float] = []
        self._hot_pore: list[int] = []
        self.H = 2.8 * float(np.mean(fluid.network.volume)) / fluid.injection_rate
        self._fine_rate: float | None = None
        self._reach = 0.0  # how far the last window reached beyond its hot pores, per sqrt(H)
        self._kappa = 0.5  # the least reach, per sqrt(H rho) (see _floor)
        self.stats = dict.fromkeys(STATS, 0)
        #: The last call ended inside a pore drained at a single rate (see :meth:`advance`),
        #: with these sweeps and this model time spent on it so far.
        self._single_open = False
        self._single_sweeps = 0.0
        self._single_span = 0.0
        self.last: dict[str, Any] = {}  # the last macro step, for diagnostics

    def sweep_field(self, box: np.ndarray) -> Sweep:
        """What a sweep over ``box`` reads
        (:func:`porenet.kinds.viscous.kernels.chebyshev.sweep`)."""
        f = self.fluid
        net, cond, front = f.network, f.conductances, f.front
        return Sweep(net.grid_n, box, int(f.flow.counters[Count.N_ACTIVE]), front.pores,
                     front.pore_slot, net.indptr, net.neighbour, net.throat, cond.between,
                     cond.outlet, net.inverse_volume, self._scratch, box)  # fmt: skip

    # -- where -----------------------------------------------------------------------------
    def _menisci(self, drained: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The frontier throats, their undrained pores and how far each is below its
        threshold (``<= 0``: at or above it; latched menisci count as at it)."""
        f = self.fluid
        flow, tp = f.flow, f.network.throat_pores
        front = f.front.throats[: int(flow.counters[Count.N_FRONT])]
        a, b = tp[front, 0], tp[front, 1]
        pore = np.where(drained[a], b, a)
        pinv = flow.totals[Total.INVADING_PRESSURE]
        gap = f.conductances.entry_pressure[front] * (1.0 - 1e-9) - (pinv - flow.pressure[pore])
        if f.config.meniscus == "latching":
            gap = np.where(flow.latched[front], -1.0, gap)
        return front, pore, gap

    def _hot_box(self, drained: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The box of the hot pores (rows ``[b0, b1)``, columns ``[b2, b3)``) and the coarse
        step's sources: the pump's rate shared among the pores of the menisci at their
        threshold, or given to the pore of the one nearest to it."""
        f, n = self.fluid, self.n
        t = float(f.flow.totals[Total.TIME])
        horizon = t - self.memory * self.H
        keep = [k for k, s in enumerate(self._hot_time) if s >= horizon]
        self._hot_time = [self._hot_time[k] for k in keep]
        self._hot_pore = [self._hot_pore[k] for k in keep]
        _, pore, gap = self._menisci(drained)
        sources = np.unique(pore[gap <= 0])
        if sources.size == 0 and pore.size:
            sources = pore[np.argmin(gap)][None]
        last = f.records.order[int(f.flow.counters[Count.EVENTS]) - 1 :][:1]
        pores = np.concatenate([np.array(self._hot_pore, dtype=np.int64), sources, last])
        rows, cols = pores // n, pores % n
        box = np.array([rows.min(), rows.max() + 1, cols.min(), cols.max() + 1], dtype=np.int64)
        rates = np.full(sources.size, f.injection_rate / max(sources.size, 1))
        return box, sources.astype(np.int64), rates

    def _grown(self, hot: np.ndarray, reach: int) -> np.ndarray:
        """The hot box widened by ``reach`` pores, in the active box."""
        nbox = self.fluid.front.box
        return np.array(
            [
                max(hot[0] - reach, nbox[0]),
                min(hot[1] + reach, nbox[1]),
                max(hot[2] - reach, nbox[2]),
                min(hot[3] + reach, nbox[3]),
            ],
            dtype=np.int64,
        )

    def _needed(self, hot: np.ndarray, ebox: np.ndarray) -> int:
        """How far beyond the hot box the window must reach to hold the coarse step's pores
        over the window tolerance with :attr:`error_margin` to spare (and
        :attr:`hot_margin` at least)."""
        if ebox[1] <= ebox[0]:
            return self.hot_margin
        far = max(hot[0] - ebox[0], ebox[1] - hot[1], hot[2] - ebox[2], ebox[3] - hot[3])
        return max(self.hot_margin, int(far) + self.error_margin)

    def _floor(self, h: float) -> int:
        """The least reach of a window for a coarse step of ``h``: ``kappa sqrt(h rho)``
        pores (and :attr:`hot_margin`), where the coarse step's stand-in for the menisci has
        become indistinguishable from them; ``kappa`` follows the refluxed volumes."""
        r = self._kappa * math.sqrt(h * self.fluid.spectral_radius)
        return max(self.hot_margin, math.ceil(r))

    def _predicted_reach(self, h: float) -> int:
        """The window's reach beyond the hot box for a coarse step of ``h``, from what the
        last ones needed (it grows like ``sqrt(h)``)."""
        return max(self.hot_margin, math.ceil(self._reach * math.sqrt(h)) + 1)

    # -- one call ---------------------------------------------------------------------------
    def advance(self, state: Any, budget: int, t_end: float, step_chunk: int) -> int:
        """Drain up to ``budget`` pores (or take about ``step_chunk`` fine steps) in macro
        steps; returns a :class:`~porenet.kinds.viscous.kernels.state.Status`."""
        counters, totals = self.fluid.flow.counters, self.fluid.flow.totals
        events0, steps0 = int(counters[Count.EVENTS]), int(counters[Count.STEPS])
        while True:
            done = int(counters[Count.EVENTS]) - events0
            if done >= budget or int(counters[Count.STEPS]) - steps0 >= step_chunk:
                return Status.BUDGET
            if totals[Total.TIME] >= t_end:
                return Status.END_TIME
            # a macro step is never cut by ``step_chunk``; a pore drained at a single rate is
            # finished first if the last call ended inside it: where calls end changes nothing
            status = None if self._single_open else self._macro_step(state, budget - done, t_end)
            if status is None:  # no window worth it: one pore at a single rate
                left = step_chunk - (int(counters[Count.STEPS]) - steps0)
                status = self._single_rate(state, t_end, left)
                if status != Status.BUDGET:
                    return status
                continue
            if status == Status.CUT or (status == Status.END_TIME and totals[Total.TIME] < t_end):
                continue
            if status != Status.BUDGET:
                return status

    def _single_rate(self, state: Any, t_end: float, step_budget: int) -> int:
        """Single-rate RKC steps until a pore drains (or ``step_budget`` steps, after which
        the next call goes on with this pore: :attr:`_single_open`)."""
        f = self.fluid
        counters, totals = f.flow.counters, f.flow.totals
        before, t_before = int(counters[Count.EVENTS]), float(totals[Total.TIME])
        sweeps = f.rkc_sweeps()
        status = f.rkc_steps(1, t_end, step_budget)
        sweeps = f.rkc_sweeps() - sweeps
        self._single_open = status == Status.BUDGET and int(counters[Count.EVENTS]) == before
        self._single_sweeps += sweeps
        self._single_span += float(totals[Total.TIME]) - t_before
        self.stats["single_rate_sweeps"] += int(sweeps)
        self.stats["single_rate_pores"] += int(counters[Count.EVENTS]) - before
        self._note_drained(before)
        if not self._single_open:
            self._learn_fine_rate(self._single_sweeps, self._single_span)
            self._single_sweeps = self._single_span = 0.0
            # the next macro step starts from at least twice the step RKC is taking
            from porenet.kinds.viscous.kernels.rkc import Slot

            self.H = max(self.H, 2.0 * f.rkc.memory[Slot.H])
        return status

    def _coarse(self, state: Any, t_end: float) -> tuple[float, np.ndarray, np.ndarray] | None:
        """An accepted coarse step and its window: the step's length, the window and the hot
        box; None when no window below :attr:`max_share` of the active box is found with at
        least :attr:`min_stages` stages. The ring's shadow sums must run in the coarse step,
        so they run for several nested candidate windows (:data:`LEVELS` times the reach the
        last steps needed); the smallest that holds the step's pores over the window
        tolerance with :attr:`error_margin` to spare is kept, and the step is redone with
        larger ones when none does."""
        f, n, win = self.fluid, self.n, self.win
        wi, ring_i = win.ints, win.ring_index
        flow = f.flow
        tol = f.config.tolerance * f.pressure_scale
        rho = f.spectral_radius
        menisci0, pump0 = f.no_menisci()
        hot, sources, rates = self._hot_box(state.drained)
        planned = self._plan(hot)
        if planned is None:
            return None
        f.rates_changed()  # the coarse steps grow the box and use F_E's buffers as scratch
        h = min(planned, t_end - float(flow.totals[Total.TIME]), longest_step(MAX_STAGES, rho))
        least = 0
        for _attempt in range(self.max_attempts):
            m = stage_count(h, rho)
            if m < self.min_stages:
                return None
            nbox = f.front.box
            grow_where_reached(nbox, n, flow.pressure, f.config.pressure_floor, m + 1)
            limit = self.max_share * _area(nbox)
            floor = self._floor(h)
            base = max(self._predicted_reach(h), least, floor)
            reaches = sorted({math.ceil(c * base) for c in LEVELS} | {least})
            boxes = []
            for reach in reaches:
                box = self._grown(hot, max(reach, floor))
                if _area(box) > limit:
                    break
                if not boxes or box.tolist() != boxes[-1].tolist():
                    boxes.append(box)
            if not boxes:
                self.stats["coarse_rejected_steps"] += 1
                h *= 0.5
                least = 0
                continue
            starts = [0]
            for box in boxes:
                starts.append(
                    starts[-1] + multirate.window_ring(n, box, nbox, ring_i[:, starts[-1] :])
                )
            wi[WindowInt.N_RING] = starts[-1]
            wi[WindowInt.N_OUTLET] = multirate.outlet_links(
                n, nbox, f.conductances.outlet, ring_i, wi[WindowInt.N_RING]
            )
            win.box[:] = boxes[-1]
            field = self.sweep_field(nbox)
            step = multirate.CoarseStep(h, m, sources, rates, menisci0, pump0,
                                        self.window_tolerance * tol)  # fmt: skip
            outflow = f.sized(multirate.coarse_step)(
                field, flow.pressure, win, step, f.rkc.stages, f.rkc.f0, f.rkc.fnew,
                f.rkc.zero, self._p1, self._ebox,
            )  # fmt: skip
            if not math.isfinite(outflow):
                raise NumericalError(
                    f"viscous model (local time steps): non-finite coarse step at "
                    f"t = {flow.totals[Total.TIME]:g} (scaled) after "
                    f"{int(flow.counters[Count.STEPS])} steps and "
                    f"{int(flow.counters[Count.EVENTS])} drained pores"
                )
            self.stats["coarse_stage_sweeps"] += m
            self.stats["coarse_pore_stages"] += m * _area(nbox)
            needed = self._needed(hot, self._ebox)
            measured = max(needed - 1, 0) / math.sqrt(h)
            self._reach = measured if self._reach == 0.0 else 0.8 * self._reach + 0.2 * measured
            want = self._grown(hot, needed)
            for k, box in enumerate(boxes):
                if (
                    box[0] <= want[0]
                    and box[1] >= want[1]
                    and box[2] <= want[2]
                    and (box[3] >= want[3])
                ):
                    n_ring, n_outlet = wi[WindowInt.N_RING], wi[WindowInt.N_OUTLET]
                    self._keep_ring(starts[k], starts[k + 1], n_ring, n_ring + n_outlet)
                    win.box[:] = box
                    return h, box, hot
            self.stats["coarse_rejected_steps"] += 1
            if _area(want) > limit:
                h *= 0.5  # no window within the share holds the step's errors
                least = 0
            else:
                least = needed
        return None

    def _keep_ring(self, lo: int, hi: int, out_lo: int, out_hi: int) -> None:
        """Keep the ring entries ``[lo, hi)`` of the chosen window and the outlet links
        ``[out_lo, out_hi)`` after them, with their coarse volumes."""
        win = self.win
        ring_i, ring_f = win.ring_index, win.ring_value
        keep = np.r_[lo:hi, out_lo:out_hi]
        ring_i[:, : keep.size] = ring_i[:, keep]
        ring_f[Ring.COARSE, : keep.size] = ring_f[Ring.COARSE, keep]
        win.ints[WindowInt.N_RING] = hi - lo
        win.ints[WindowInt.N_OUTLET] = out_hi - out_lo

    def _macro_step(self, state: Any, budget: int, t_end: float) -> int | None:
        f, win = self.fluid, self.win
        wi = win.ints
        flow, counters, totals = f.flow, f.flow.counters, f.flow.totals
        t0 = float(totals[Total.TIME])
        coarse = self._coarse(state, t_end)
        if coarse is None:
            return None
        h, wbox, hot = coarse
        nbox = f.front.box
        # a pore that drains within half the hot pores' distance to an open edge ends it
        gaps = [hot[0] - wbox[0], wbox[1] - hot[1], hot[2] - wbox[2], wbox[3] - hot[3]]
        wi[WindowInt.MARGIN] = max(2, min(gaps) // 2)
        wi[WindowInt.CUT_REASON] = wi[WindowInt.CUT_PORE] = -1
        field = self.sweep_field(nbox)
        multirate.start_fine(win, flow.pressure, self._p1, field, t0, h)
        drained = state.drained
        tp, entry = f.network.throat_pores, f.conductances.entry_pressure
        n_w, wi[WindowInt.N_FAR] = multirate.split_front(
            self.n, wbox, f.front.throats, int(counters[Count.N_FRONT]), tp, drained,
            self._wfront, self._wfpos, win.far,
        )  # fmt: skip
        win.floats[WindowFloat.FAR_LEVEL] = multirate.far_level(
            win.far, wi[WindowInt.N_FAR], tp, drained, entry, win.p0, win.rate, h
        )
        inside = self._wfront[:n_w].copy()
        ell_before = flow.meniscus_length[inside].copy()
        events0 = int(counters[Count.EVENTS])
        sweeps0 = f.rkc_sweeps()
        # the window's own counters: its front is the window's menisci
        window_counters = counters.copy()
        window_counters[Count.N_FRONT] = n_w
        status = f.rkc_steps(budget, t0 + h, f.config.max_steps, win,
                             (self._wfront, self._wfpos, window_counters))  # fmt: skip
        shared = [Count.EVENTS, Count.STEPS, Count.N_ACTIVE, Count.WHERE, Count.BREAKTHROUGH]
        counters[shared] = window_counters[shared]
        drained_now = f.records.order[events0 : int(window_counters[Count.EVENTS])]
        multirate.merge_front(f.network, drained, f.front, counters, drained_now, self._wfront,
                              self._wfpos, int(window_counters[Count.N_FRONT]))  # fmt: skip
        if status == Status.NO_MENISCUS and counters[Count.N_FRONT] > 0:
            status = Status.CUT  # the window's menisci are gone, not all of them
        t_e = float(totals[Total.TIME])
        theta = (t_e - t0) / h
        stored, far_out, reflux = multirate.far_update(
            field, flow.pressure, self._p1, f.network.volume, state.drained, win, theta
        )
        totals[Total.STORED_DEFENDER] += stored
        totals[Total.OUTFLOW] += far_out
        totals[Total.IN_TRANSIT] = 0.0
        w_pores = _area(wbox)
        fine = f.rkc_sweeps() - sweeps0
        self.stats["window_pore_stages"] += int(fine * w_pores)
        self.stats["macro_steps"] += 1
        self._note_drained(events0)
        moved = inside[flow.meniscus_length[inside] != ell_before]
        if moved.size:
            self._hot(t_e, tp[moved, 0], tp[moved, 1], state.drained)
        if status == Status.CUT:
            self.stats["macro_cuts"] += 1
            if wi[WindowInt.CUT_REASON] == Cut.FAR_MENISCUS:
                self._hot_time.append(t_e)
                self._hot_pore.append(int(wi[WindowInt.CUT_PORE]))
        self._learn_fine_rate(fine, t_e - t0)
        # the window's least reach follows the refluxed change (kept between a quarter and
        # all of reflux_fraction of the tolerance); next H: at most twice this one and what
        # the refluxed change (~ H^2) allows, the cheapest length below that
        tol = f.config.tolerance * f.pressure_scale
        if reflux > self.reflux_fraction * tol:
            self._kappa = min(self._kappa * 1.25, 4.0)
        elif reflux < 0.25 * self.reflux_fraction * tol:
            self._kappa = max(self._kappa * 0.9, 0.1)
        fac = 2.0
        if reflux > 0:
            fac = min(fac, math.sqrt(self.reflux_fraction * tol / reflux))
        cap = h * max(fac, 0.2)
        self.H = min(cap, self._cheapest(cap, hot)[0])
        self.last = {"h": h, "theta": theta, "reflux": reflux / tol, "status": status,
                     "window": w_pores, "hot": _area(hot),
                     "next": self.H}  # fmt: skip
        return status

    def _learn_fine_rate(self, sweeps: float, span: float) -> None:
        """Fine sweeps (RKC stages and explicit steps) per unit of time, smoothed over the
        last few pores' worth of time: what the window costs per pore it holds."""
        if span <= 0:
            return
        weight = min(1.0, span / (4.0 * self.H))
        rate = sweeps / span
        if self._fine_rate is None:
            self._fine_rate = rate
        else:
            self._fine_rate = (1.0 - weight) * self._fine_rate + weight * rate

    def _cheapest(self, cap: float, hot: np.ndarray) -> tuple[float, float]:
        """The macro-step length up to ``cap`` that minimises the pore updates per unit time,
        and that cost: the coarse step's stages over the active box per ``H`` plus the fine
        sweeps over a window whose reach beyond the hot pores grows like ``sqrt(H)`` (windows
        over :attr:`max_share` of the active box are not an option). ``(cap, inf)`` before
        the fine sweeps' rate is known."""
        f = self.fluid
        if self._fine_rate is None:
            return cap, math.inf
        nbox = f.front.box
        n_rows, n_cols = int(nbox[1] - nbox[0]), int(nbox[3] - nbox[2])
        rho = f.spectral_radius
        best, best_cost = cap, math.inf
        shortest = longest_step(self.min_stages, rho)
        for k in range(max(math.ceil(4.0 * math.log2(shortest / cap)), -80), 1):
            h = cap * 2.0 ** (k / 4.0)
            r = max(self._predicted_reach(h), self._floor(h))
            area = min(int(hot[1] - hot[0]) + 2 * r, n_rows) * min(
                int(hot[3] - hot[2]) + 2 * r, n_cols
            )
            if area > self.max_share * n_rows * n_cols:
                continue
            cost = stage_count(h, rho) * n_rows * n_cols / h + self._fine_rate * area
            if cost < best_cost:
                best, best_cost = h, cost
        return best, best_cost

    def _plan(self, hot: np.ndarray) -> float | None:
        """The length of the next macro step, the cheapest up to ``H``; None when a macro step
        is predicted to cost more than :attr:`gain` times single-rate steps over the whole
        active box, or the active box is smaller than :attr:`min_box` (unless ``on``)."""
        f = self.fluid
        nbox = f.front.box
        area = _area(nbox)
        if area < self.min_box and not self.always:
            return None
        h, cost = self._cheapest(self.H, hot)
        if self._fine_rate is not None and not cost < self.gain * self._fine_rate * area:
            return None
        return h

    def _hot(self, t: float, a: np.ndarray, b: np.ndarray, drained: np.ndarray) -> None:
        """Mark the pores entered by the menisci of throats (a, b) hot at ``t``."""
        pore = np.where(drained[a] & ~drained[b], b, a)
        self._hot_time.extend([t] * len(pore))
        self._hot_pore.extend(int(k) for k in pore)

    def _note_drained(self, since: int) -> None:
        f = self.fluid
        k = int(f.flow.counters[Count.EVENTS])
        if k > since:
            self._hot_time.extend(float(x) for x in f.records.series[since:k, Column.TIME])
            self._hot_pore.extend(int(x) for x in f.records.order[since:k])
