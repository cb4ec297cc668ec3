"""Builds the models a Plan calls for and runs the loop (see porenet.core.interfaces).

Length (over the ~500 lines of docs/architecture.md's rule): one class, the run loop, with what
is tied to the state of a run: starting and ending the phases, checkpoints (pickling and
resuming the same object) and the run's record (RunData) assembled from the models' outputs.
Each is a few methods on the same attributes; in separate modules they would read the
Simulation's attributes from outside.
"""

from __future__ import annotations

import logging
import sys
import time
from typing import TYPE_CHECKING, Any

import numpy as np

from porenet._version import __version__
from porenet.core.errors import ConfigError, NumericalError, PluginError
from porenet.core.interfaces import (
    Classifier,
    Coupler,
    FluidModel,
    Lattice,
    Observer,
    RunContext,
    RunView,
    SolidModel,
)
from porenet.core.kinds import implied_observers
from porenet.core.plan import Plan, make_plan, plan_summary
from porenet.core.registry import Registry
from porenet.core.state import State
from porenet.core.units import Scales
from porenet.jit.compilation import CompileNotice
from porenet.jit.threads import CALL_SECONDS, ThreadGovernor, thread_setting
from porenet.kernels.bursts import burst_sizes
from porenet.result import RunData, RunResult

if TYPE_CHECKING:  # pragma: no cover
    from porenet.io.checkpoint import CheckpointSchedule

log = logging.getLogger(__name__)

#: Chunk size (events) when no observer or coupler asks for a smaller one.
UNBOUNDED = 1 << 62
#: Fields of the run data that observers fill (:meth:`Observer.run_data`), each a list.
RUN_DATA_FIELDS = ("snapshots",)


class Simulation:
    """One run: a Lattice, a FluidModel, an optional SolidModel + Coupler, Observers, one State.

    Build it from a :class:`~porenet.core.plan.Plan` (or with :meth:`from_scene`) and call
    :meth:`run`. Random numbers come only from the scene's seed: the lattice and the models get
    independent streams spawned from ``SeedSequence(seed)``.
    """

    def __init__(
        self,
        plan: Plan,
        registry: Registry | None = None,
        observers: list[Observer] | tuple[Observer, ...] = (),
        report: bool = False,
    ) -> None:
        from porenet.hooks import get_registry

        t0 = time.perf_counter()
        self.plan = plan
        self.registry = registry or get_registry()
        #: ``report``: write what the run does to stderr (a start line, compiling kernels).
        self.report = report
        self.compile_notice = CompileNotice(enabled=report)
        #: Chooses the threads of the fluid's parallel kernels call by call, built by
        #: :meth:`run` (None: the fluid model has none); its counters go into the summary.
        self.threads: ThreadGovernor | None = None
        scene = plan.scene
        lattice_seed, model_seed = np.random.SeedSequence(scene.seed).spawn(2)
        try:
            lattice_cls = self.registry.get("lattice", scene.lattice.kind).load()
            with self.compile_notice.phase(f"the {scene.lattice.kind!r} lattice"):
                self.lattice: Lattice = lattice_cls(
                    scene.lattice, np.random.default_rng(lattice_seed)
                )
        except ValueError as exc:
            raise ConfigError(f"lattice: {exc}") from exc
        try:  # the injection site must name pores of this lattice
            inlets = self.lattice.inlet_pores(scene.injection.at)
            outlet = self.lattice.outlet_mask(scene.injection.at)
        except ValueError as exc:
            raise ConfigError(f"injection.at: {exc}") from exc
        if inlets.size == 0 or not np.any(outlet):
            raise ConfigError(
                f"injection.at = {scene.injection.at!r}: this site has no "
                f"{'pore' if inlets.size == 0 else 'outlet'} on this lattice "
                '(docs/lattices.md, "Injection sites and outlets")'
            )
        self.scales = Scales.from_physics(
            scene.lattice.pore_size,
            scene.fluid.interfacial_tension,
            getattr(scene.fluid, "viscosity", None),
        )
        self.context = RunContext(
            self.scales,
            scene.injection,
            scene.stop,
            np.random.default_rng(model_seed),
            deformable=bool(plan.effects.get("aperture_feedback", False)),
        )
        fluid_cls = self.registry.get("fluid", scene.fluid.kind).load()
        self.fluid: FluidModel = fluid_cls(scene.fluid, self.lattice, self.context)
        self.solid: SolidModel | None = None
        self.coupler: Coupler | None = None
        if plan.builds("solid"):
            solid_cls = self.registry.get("solid", scene.solid.kind).load()
            self.solid = solid_cls(scene.solid, self.lattice, self.context)
            coupler_kind = getattr(scene.solid, "coupler", None)
            if coupler_kind is None:
                raise ConfigError(f"solid kind {scene.solid.kind!r} names no coupler")
            coupler_entry = self.registry.get("coupler", coupler_kind)
            self.coupler = coupler_entry.load()(scene.solid, self.context)  # type: ignore[misc]
            self.fluid.step_limit = self.coupler.max_steps()
        self.observers: list[Observer] = []
        for obs_config in (*scene.observers, *implied_observers(scene.fluid)):
            self.observers.append(self.registry.get("observer", obs_config.kind).load()(obs_config))
        self.observers.extend(observers)
        #: Labels the pattern at the end (scene section ``[classifier]``), if the plan asks.
        self.classifier: Classifier | None = None
        if plan.builds("classifier"):
            entry = self.registry.get("classifier", scene.classifier.kind)
            self.classifier = entry.load()(scene.classifier)  # type: ignore[misc]
        self.state = State.initial(self.lattice.n_pores, self.lattice.initial_apertures)
        self.build_time = time.perf_counter() - t0
        #: Wall time of the run before the current stretch (building, earlier processes).
        self._wall_before = self.build_time
        self._clock = time.perf_counter()
        self._started = False

    @classmethod
    def from_scene(
        cls,
        scene: Any,
        overrides: list[str] | tuple[str, ...] = (),
        *,
        output: Any = None,
        progress: bool = False,
        registry: Registry | None = None,
        network: Any = None,
    ) -> Simulation:
        """Validate ``scene`` (path, dict or SceneConfig), plan it and build the simulation.

        ``progress``: show a start line and progress on stderr (a status line on a terminal,
        a line every ~30 s or ~10 % of the estimate elsewhere), and say when kernels compile.
        ``network``: a network held in memory (an OpenPNM or PoreSpy network dict, or an
        OpenPNM ``Network``) for the scene's network lattice, saved as the file its
        ``lattice.file`` names (:mod:`porenet.io.networks`).
        """
        from porenet.config.loading import load_scene
        from porenet.hooks import get_registry
        from porenet.io.progress import Progress
        from porenet.io.writer import RunFileWriter

        if network is not None:
            from porenet.io.networks import save_network

            overrides = [*overrides, f"lattice.file={save_network(network)}"]
        registry = registry or get_registry()
        config = load_scene(scene, overrides, registry=registry)
        plan = make_plan(config, registry, output=output, progress=progress)
        extra: list[Observer] = []
        if progress:
            extra.append(Progress())
        if output is not None:
            extra.append(RunFileWriter(output))
        return cls(plan, registry, extra, report=progress)

    def _budget(self) -> int:
        state, stop = self.state, self.plan.scene.stop
        budget = UNBOUNDED
        if stop.max_drained is not None:
            budget = max(0, stop.max_drained - state.n_drained)
        for obs in self.observers:
            due = obs.trigger.events_until_due(state)
            if due is not None:
                budget = min(budget, due)
        if self.coupler is not None:
            limit = self.coupler.max_events()
            if limit is not None:
                budget = min(budget, limit)
        return budget

    def _stop_reason(self) -> str | None:
        state, stop = self.state, self.plan.scene.stop
        if stop.max_drained is not None and state.n_drained >= stop.max_drained:
            return "max_drained"
        if stop.at == "breakthrough" and state.breakthrough:
            return "breakthrough"
        if self.fluid.exhausted:
            return self.fluid.stop_reason or "complete"
        return None

    def run(self, checkpoints: CheckpointSchedule | None = None) -> RunResult:
        """Run to the stop criterion and return the result (observers closed, file written).

        ``checkpoints``: write a checkpoint of the run when the schedule says so, between two
        calls of the fluid model, and remove it once the run file is written
        (docs/run-file.md, "Checkpoints"). A simulation loaded from a checkpoint
        (:meth:`resume`) goes on from where it was.
        """
        self._clock = time.perf_counter()
        if not self._started:
            self._start()
        state = self.state
        while (reason := self._stop_reason()) is None:
            self._iterate()
            if checkpoints is not None and checkpoints.due(state):
                checkpoints.write(self)
        result = self._finish(reason)
        if checkpoints is not None:
            checkpoints.remove()
        return result

    def _phases(self) -> tuple[str, str, str]:
        """The compile notice's names of the fluid's setup, its steps and the solid."""
        scene = self.plan.scene
        fluid = f"the {scene.fluid.kind!r} fluid model"
        solid = f"the {scene.solid.kind!r} solid" if self.solid is not None else ""
        return fluid, f"{fluid}'s steps", solid

    def _start(self) -> None:
        """Set the models up and attach the observers (once per run)."""
        state, notice = self.state, self.compile_notice
        fluid_phase, _, solid_phase = self._phases()
        self._log_start()
        with notice.phase(fluid_phase):
            self.fluid.setup(state)
        if self.solid is not None:
            with notice.phase(solid_phase):
                self.solid.setup(state)
        view = self.view()
        for obs in self.observers:
            obs.trigger.reset()
            obs.attach(view)
        self.threads = (
            ThreadGovernor(thread_setting()) if self.fluid.parallel_work() is not None else None
        )
        self._started = True
        self._observe()  # those due at once (a saturation the inlets already reach)

    def _iterate(self) -> None:
        """One call of the fluid model, the coupling that follows it and the observers."""
        state, notice = self.state, self.compile_notice
        _, steps_phase, solid_phase = self._phases()
        time_before = state.time
        events = self._advance(steps_phase)
        if events == 0 and state.time == time_before and not self.fluid.exhausted:
            raise NumericalError(
                f"fluid model {type(self.fluid).__name__} made no progress (no pore drained, "
                f"time unchanged) after {state.n_drained} drained pores at step {state.step}"
            )
        if self.coupler is not None and self.solid is not None:
            with notice.phase(solid_phase):
                exchanged = self.coupler.exchange(state, self.solid, events)
            if exchanged:
                self.fluid.apertures_changed(state, self.coupler.changed_throats)
        self._observe()

    def _observe(self) -> None:
        """Show the State to the observers whose trigger fires now."""
        state = self.state
        for obs in self.observers:
            if obs.trigger.fires(state):
                obs.observe(state)

    def view(self) -> RunView:
        """What the observers see of this run (:class:`~porenet.core.interfaces.RunView`)."""
        cost = self.plan.cost
        return RunView(
            scene=self.plan.scene,
            lattice=self.lattice,
            scales=self.scales,
            expected_drained=None if cost is None else cost.drained,
            solid_fields=None if self.solid is None else self.solid.snapshot,
            wall_time=self.wall_time,
        )

    def wall_time(self) -> float:
        """Wall time of the run so far, in seconds: building it, and every stretch it ran
        (in one process or across checkpoints)."""
        return self._wall_before + time.perf_counter() - self._clock

    def _finish(self, reason: str) -> RunResult:
        """Finalize the fluid, gather the result, classify it and close the observers."""
        state, notice, scene = self.state, self.compile_notice, self.plan.scene
        with notice.phase("the end of the run"):
            self.fluid.finalize(state)
        self._check_finite()
        wall = self.wall_time()
        result = RunResult(self._data(reason, wall), state, self.lattice, self.plan)
        if self.classifier is not None:
            from porenet.analysis.classify import classify_run

            with notice.phase(f"the {scene.classifier.kind!r} classifier"):
                verdict = classify_run(result.data, self.classifier, scene.classifier.kind)
            result.data.summary.update(verdict)
            log.info("pattern: %s", verdict)
        for obs in self.observers:
            obs.close(state, result)
        log.info("run finished: %s after %d pores in %.3f s", reason, state.n_drained, wall)
        return result

    # -- checkpoints ----------------------------------------------------------------------
    def __getstate__(self) -> dict[str, Any]:
        """What a checkpoint pickles: everything but the registry, the compile notice and the
        plan, which the loading process rebuilds (the plan from the scene)."""
        out = dict(self.__dict__)
        for name in ("registry", "compile_notice", "plan"):
            out.pop(name, None)
        plan = self.plan
        out["_plan_inputs"] = (
            plan.scene.model_dump(mode="json"),
            None if plan.output is None else str(plan.output),
            plan.progress,
        )
        out["_wall_before"] = self.wall_time()
        return out

    def __setstate__(self, values: dict[str, Any]) -> None:
        """Restore what a checkpoint pickled; :meth:`resume` then plans the scene again with
        the registry it is given (:meth:`_replan`)."""
        self.__dict__.update(values)
        self.compile_notice = CompileNotice(enabled=self.report)
        self._clock = time.perf_counter()  # this process's clock; _wall_before holds the past

    def _replan(self, registry: Registry) -> None:
        """Validate and plan the pickled scene again with ``registry`` (after unpickling)."""
        from porenet.config.loading import load_scene

        scene, output, progress = self.__dict__.pop("_plan_inputs")
        self.registry = registry
        config = load_scene(scene, registry=registry)
        self.plan = make_plan(config, registry, output=output, progress=progress)

    def checkpoint_header(self) -> dict[str, Any]:
        """The header fields of a checkpoint of this run (:mod:`porenet.io.checkpoint`)."""
        from porenet.io import checkpoint as ck

        state, plan = self.state, self.plan
        models = (self.lattice, self.fluid, self.solid, self.coupler, self.classifier,
                  *self.observers)  # fmt: skip
        classes = tuple(type(m) for m in models if m is not None)
        return {
            "porenet_version": __version__,
            "code_fingerprint": ck.code_fingerprint(),
            "plugin_sources": ck.plugin_sources(classes),
            "scene_digest": ck.scene_digest(plan.scene.model_dump(mode="json")),
            "scene_name": plan.scene.name,
            "output": None if plan.output is None else str(plan.output),
            "n_drained": int(state.n_drained),
            "step": int(state.step),
            "model_time": float(state.time),
            "wall_time_s": self.wall_time(),
            "written": ck.now_text(),
        }

    @classmethod
    def resume(
        cls,
        path: Any,
        *,
        output: Any = None,
        progress: bool = False,
        registry: Registry | None = None,
    ) -> Simulation:
        """The simulation saved in the checkpoint at ``path``, ready for :meth:`run` to go on
        (``output``: write the run file there instead of where the run meant to;
        ``progress``: show progress on stderr; ``registry``: the kinds to plan the scene
        with again, default the process's, which must hold every kind the scene uses).

        Raises
        ------
        porenet.io.checkpoint.CheckpointError
            ``path`` is not a checkpoint, is damaged, or was written by other code.
        """
        from pathlib import Path

        from porenet.io.checkpoint import load_checkpoint
        from porenet.io.progress import Progress
        from porenet.io.writer import RunFileWriter

        sim, _ = load_checkpoint(path)
        if not isinstance(sim, cls):
            from porenet.io.checkpoint import CheckpointError

            raise CheckpointError(f"{path} holds no porenet simulation")
        if registry is None:
            from porenet.hooks import get_registry

            registry = get_registry()
        sim._replan(registry)
        sim.report = progress
        sim.compile_notice = CompileNotice(enabled=progress)
        kept: list[Observer] = []
        for obs in sim.observers:
            if isinstance(obs, Progress):
                continue  # shown or not as this process asks
            if isinstance(obs, RunFileWriter) and output is not None:
                obs = RunFileWriter(output)
            kept.append(obs)
        view = sim.view()
        if progress:
            bar = Progress()
            bar.trigger.reset()
            bar.attach(view)
            kept.insert(0, bar)
        for obs in kept:
            obs.resumed(view)
        sim.observers = kept
        if output is not None:
            import dataclasses

            sim.plan = dataclasses.replace(sim.plan, output=Path(output))
        return sim

    def _advance(self, phase: str) -> int:
        """One call of the fluid model, on the threads the governor picks, aiming at its
        wall time (:mod:`porenet.jit.threads`)."""
        fluid, governor, notice = self.fluid, self.threads, self.compile_notice
        times = [
            t for obs in self.observers if (t := obs.trigger.next_time(self.state)) is not None
        ]
        fluid.stop_time = min(times) if times else None
        if governor is None:
            fluid.call_seconds = CALL_SECONDS
            with notice.phase(phase):
                return fluid.advance(self.state, self._budget())
        governor.before_call()
        fluid.call_seconds = governor.call_seconds()
        work0, compiled0, t0 = fluid.parallel_work() or 0.0, notice.counter(), time.perf_counter()
        with notice.phase(phase):
            events = fluid.advance(self.state, self._budget())
        governor.after_call(
            time.perf_counter() - t0,
            (fluid.parallel_work() or 0.0) - work0,
            compiled=notice.counter() != compiled0,
        )
        return events

    def _log_start(self) -> None:
        """INFO: what runs and the plan's estimate; DEBUG: the whole plan."""
        scene, cost = self.plan.scene, self.plan.cost
        log.info(
            "run start: scene %r, %s lattice of %d pores and %d throats, fluid %s, solid %s%s; "
            "built in %.3f s",
            scene.name, scene.lattice.kind, self.lattice.n_pores, self.lattice.n_throats,
            scene.fluid.kind, scene.solid.kind if self.solid is not None else "none (rigid)",
            f" (coupler {scene.solid.coupler})" if self.coupler is not None else "",
            self.build_time,
        )  # fmt: skip
        if cost is not None:
            log.info("estimate (docs/cost.md): %s", cost.summary())
        log.debug("plan:\n%s", self.plan.describe())
        if self.report:
            sys.stderr.write(f"porenet: {self.start_line()}\n")
            sys.stderr.flush()

    def start_line(self) -> str:
        """What runs, on what, and what the plan expects (``porenet run`` prints it)."""
        scene, cost, lat = self.plan.scene, self.plan.cost, self.lattice
        solid = f"{scene.solid.kind!r} solid" if self.solid is not None else "rigid medium"
        text = (
            f"run {scene.name!r}: {scene.fluid.kind!r} fluid model, {solid}, "
            f"{scene.lattice.kind!r} lattice of {lat.n_pores:,} pores"
        )
        if cost is not None:
            text += f"; expect {cost.summary()} (docs/cost.md)"
        return text

    def _check_finite(self) -> None:
        state = self.state
        # Without a solid model the apertures are the lattice's, checked when it was built.
        for name in ("pressure",) if self.solid is None else ("pressure", "apertures"):
            values = getattr(state, name)
            if values is not None and not np.all(np.isfinite(values)):
                bad = int(np.flatnonzero(~np.isfinite(values))[0])
                raise NumericalError(
                    f"non-finite {name} at index {bad} after {state.n_drained} drained pores "
                    f"(t = {state.time:g} scaled)"
                )

    def _data(self, reason: str, wall: float) -> RunData:
        state, lat, sc = self.state, self.lattice, self.scales
        rec = state.record
        k = rec.size
        throat = rec.throat[:k].copy()
        pressure_si = rec.pressure[:k] * sc.pressure
        _, bursts = burst_sizes(rec.pressure[:k][throat >= 0])
        n = lat.n_pores
        summary: dict[str, Any] = {
            "n_pores": n,
            "n_drained": int(state.n_drained),
            "drained_fraction": state.n_drained / n,
            "n_trapped": int(state.trapped.sum()),
            "trapped_fraction": float(state.trapped.sum()) / n,
            "breakthrough": bool(state.breakthrough),
            "stop_reason": reason,
            "wall_time_s": wall,
            "seed": int(self.plan.scene.seed),
            "n_bursts": int(bursts.size),
            "largest_burst": int(bursts.max()) if bursts.size else 0,
        }
        summary.update(self.fluid.summary(state))
        if self.solid is not None:
            summary.update(self.solid.summary(state))
        if self.coupler is not None:
            summary.update(self.coupler.summary(state))
        if self.threads is not None:
            summary.update(self.threads.summary())
        summary["compile_time_s"] = self.compile_notice.compiled_seconds
        summary.update(plan_summary(self.plan))
        from porenet.analysis.suspect import suspect_physics

        suspect = suspect_physics(summary, len(lat.throat_pores))
        for sentence in suspect:
            log.warning("suspect result: %s", sentence)
        summary["physics_warnings"] = "; ".join(suspect)
        return RunData(
            porenet_version=__version__,
            scene=self.plan.scene.model_dump(mode="json"),
            pore_size=sc.length,
            grid_shape=lat.grid_shape,
            throat_pores=np.asarray(lat.throat_pores),
            pore_coords=np.asarray(lat.pore_coords) * sc.length,
            apertures=np.asarray(lat.initial_apertures) * sc.length,
            drained=state.drained.copy(),
            trapped=state.trapped.copy(),
            order=rec.order[:k].copy(),
            throat=throat,
            invasion_pressure=pressure_si,
            summary=summary,
            pressure=None if state.pressure is None else state.pressure * sc.pressure,
            invasion_time=None if sc.time is None else rec.time[:k] * sc.time,
            burst_sizes=bursts,
            final_apertures=(state.apertures * sc.length if self.solid is not None else None),
            **self._outputs(),
            **self._solid_outputs(),
            **self._observer_outputs(),
        )

    def _observer_outputs(self) -> dict[str, Any]:
        """The observers' records (:meth:`Observer.outputs`, SI) and their units, by
        observer; a name two observers share gets ``-2``, ``-3``, ... on the later ones."""
        values: dict[str, dict[str, np.ndarray]] = {}
        units: dict[str, dict[str, str]] = {}
        for obs in self.observers:
            records = obs.outputs(self.state)
            if not records:
                continue
            name, k = obs.output_name, 1
            while name in values:
                k += 1
                name = f"{obs.output_name}-{k}"
            values[name] = {key: np.asarray(v) for key, v in records.items()}
            units[name] = {key: obs.output_units.get(key, "") for key in records}
        return {"observers": values, "observer_units": units}

    def _solid_outputs(self) -> dict[str, Any]:
        """The solid model's final fields and per-update series (:meth:`SolidModel.outputs`)
        in SI."""
        if self.solid is None:
            return {}
        raw = self.solid.outputs(self.state)
        return {
            "mechanics_final": self.scales.solid_fields(raw.get("final", {})),
            "mechanics_series": self.scales.solid_fields(raw.get("series", {})),
        }

    def _outputs(self) -> dict[str, Any]:
        """The fluid model's time series (:meth:`FluidModel.outputs`), in SI, and the fields
        of the run data the observers fill (:meth:`Observer.run_data`; lists, such as the
        ``snapshots`` of two snapshot observers, are joined in the observers' order)."""
        sc = self.scales
        raw = self.fluid.outputs(self.state)
        unit = {"time": sc.time or 1.0, "invading_pressure": sc.pressure}
        for name in ("injected", "drained", "stored", "outflow", "released"):
            unit[name] = sc.volume
        out: dict[str, Any] = {}
        if "timeseries" in raw:
            out["timeseries"] = {
                k: np.asarray(v) * unit.get(k, 1.0) for k, v in raw["timeseries"].items()
            }
        for obs in self.observers:
            for name, value in obs.run_data(sc).items():
                if name not in RUN_DATA_FIELDS:
                    raise PluginError(
                        f"observer {obs.output_name!r} fills {name!r}, which is not a field "
                        f"of the run data observers fill ({', '.join(RUN_DATA_FIELDS)})"
                    )
                out[name] = [*out.get(name, []), *value]
        return out


def run(
    scene: Any,
    overrides: list[str] | tuple[str, ...] = (),
    *,
    output: Any = None,
    progress: bool = False,
    network: Any = None,
) -> RunResult:
    """Validate, plan and run a scene.

    Parameters
    ----------
    scene : str, Path, dict or SceneConfig
        A TOML file, a dict with the same structure, or a validated scene.
    overrides : list of str
        Dotted ``KEY=VALUE`` overrides (``"lattice.n=64"``), validated like the file.
    output : str or Path, optional
        Run file (HDF5) to write atomically at the end.
    progress : bool
        Show progress on a terminal or in a notebook.
    network : dict or OpenPNM Network, optional
        A network held in memory for a scene whose lattice is of kind ``network``: saved as
        an ``.npz`` file named by its content (:mod:`porenet.io.networks`) and given as
        ``lattice.file``, so it meets the checks of a file (docs/lattices.md, "Imported
        networks")::

            net = porespy.networks.snow2(image, voxel_size=1e-6).network
            porenet.run({"lattice": {"kind": "network", "pore_size": 1e-6}, "fluid": {}},
                        network=net)

    Returns
    -------
    RunResult
    """
    return Simulation.from_scene(
        scene, overrides, output=output, progress=progress, network=network
    ).run()
