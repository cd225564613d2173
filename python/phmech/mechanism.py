"""phmech.Mechanism: the builder (python/phmech/_builder.py) with its analyses, each a thin
delegate to the function of its layer module -- simulate (python/phmech/_simulate.py), modes
(_modes.py), linearize (_linearize.py), static (_statics.py), the initial configuration
(_model.py), the mesh sizing (phmech.mesh) and modal links (_modal.py) -- and ``load`` (model
files, phmech.io). docs/architecture.md, "Python layers", places each.

Conventions: SI units; twist (omega, v) and wrench (tau, f), angular part first; poses 4x4.
A beam's local x axis is its centre line; its section axes are y and z."""
from __future__ import annotations

from typing import Callable, Optional, Sequence, Union

import numpy as np

from . import io, _linearize, mesh, _modal, _model, _modes, postprocess, _simulate, _statics
from ._builder import Builder
from ._errors import ModelError
from .frames import FlexibleLink, link_of
from .results import InitialConfiguration, ModesResult, SimulationResult, StaticResult


class Mechanism(Builder):
    """A mechanism under construction: add links, bodies, pairs and wrenches, then simulate,
    compute modes or static equilibria. ``gravity`` [m/s^2] in world coordinates.

    ``strict``: when the loop closure of the initial configuration moves a given joint
    coordinate (``x0``) or a given pose beyond its tolerance, raise ModelError instead of warning
    (InitialValueWarning). Tolerances: 1e-6 rad for angles (1e-6 ``|x0|`` for ``|x0|`` > 1 rad), 1e-6 L
    for lengths, L the mechanism's size (_placement.length_scale: the largest of the link lengths,
    the pair frames' offsets and the extent of the carriers' initial origins). Either way the
    moves are listed in ``initial_adjustments`` once a model has been built.

    ``band`` [Hz] and ``frequency_tolerance``: the frequencies the model must resolve; every
    flexible link added without ``elements=`` gets the number of elements that puts its modes up
    to ``band`` within ``frequency_tolerance`` of the converged ones (phmech.mesh.choose_elements;
    ``link.mesh`` says what was chosen and the estimated error). Without a band a link gets 10
    elements. (The integrator's band, ``simulate(band=)``, is separate: what the steps resolve.)
    That choice sizes each link free in space; :meth:`sized` sizes the finished mechanism by its
    own modes (supports and couplings included)."""

    def _choose_elements(self, length, properties, band, tolerance, curvature, mass):
        return mesh.choose_elements(length, properties, band, tolerance, curvature=curvature,
                                    mass=mass)

    def _add_modal_link(self, name, L, properties, N, eps, I, H0, given, choice, mass, modes,
                        band, tol, placed) -> FlexibleLink:
        return _modal.add_modal_link(self, name, L, properties, N, eps, I, H0, given, choice, mass,
                                     modes, band, tol, placed)

    # -------------------------------------------------------------- analyses
    def initial_configuration(self) -> InitialConfiguration:
        """The initial configuration the analyses start from (tree placement from the given
        poses and x0, loop closure; see docs/user_guide.md): poses, twists, the
        InitialAdjustment table (also left in ``initial_adjustments``) and the redundant
        constraints. Warns (InitialValueWarning) or, with ``strict``, raises ModelError like
        the analyses when the loop closure moved a given value beyond its tolerance."""
        H, T, _, _ = _model.initial(self)
        return InitialConfiguration(H, T, list(self.initial_adjustments), list(self.redundant_constraints))

    # -------------------------------------------------------------- analyses
    def simulate(self, t_end: float, dt_out: float, rtol: Optional[float] = None,
                 atol: Optional[float] = None, linear_solver: str = "auto",
                 initial: Optional[StaticResult] = None, t_start: float = 0.0,
                 callback: Optional[Callable[[float, int], bool]] = None, max_step: float = 0.0,
                 max_order: Optional[int] = None, record=None, progress: bool = False,
                 error_test: str = "all", integrator: str = "generalized-alpha",
                 step: Optional[float] = None, rho_inf: Optional[float] = None,
                 band: Optional[float] = None, checkpoint=None,
                 checkpoint_every: Optional[float] = None,
                 planar: Optional[bool] = None,
                 error_check: Optional[bool] = None) -> SimulationResult:
        """Integrate from ``t_start`` to ``t_end`` [s], sampling every ``dt_out`` [s].

        The defaults are meant to be right and fast; ``simulate(t_end, dt_out)`` is the intended
        call. The default integrator is the generalized-alpha method with step-size control.
        What it promises (docs/user_guide.md, "Accuracy contract"):

        - ``rtol`` (default 1e-4) and ``atol`` [m, rad; default rtol * 1e-2]: the configuration
          (carrier positions and quaternions, joint coordinates) is kept within
          ``rtol |y| + atol`` per coordinate, in the RMS norm over the coordinates: every
          accepted step's local error estimate times the number of such steps in the run is at
          most that tolerance (a step above it is redone shorter, down to 1/1000 of the band's
          floor 1/(20 band)). A run that could not keep it warns (``phmech.AccuracyWarning``:
          the estimate reached, the tolerance, when, the remedy).
        - ``dt_out`` [s]: the output times. The steps land on them (no interpolation). A
          coarse one does not loosen the tolerance; a fine one raises the default band (below),
          which can make the run more accurate than asked.
        - ``band`` [Hz] (default 1/(2 dt_out), at least 50 / (t_end - t_start), times
          (1e-4 / rtol)^(1/3), at most 4.6x, with flexible links when rtol is below its default
          1e-4; and, for a start or a step that rings -- ``initial`` a StaticResult found
          under extra loads, the initial configuration at rest away from its loads'
          equilibrium, a load's Step -- twice the modes it rings in above the
          tolerance, at most 20x: docs/user_guide.md, "Accuracy contract"): the steps are at
          most 1/(12 band). With flexible links, the error estimate sees the motion through a
          low-pass filter at the band: the mesh's vibrations above it (axial, shear and high
          bending modes, kHz to MHz) are damped by the method's numerical dissipation
          (spectral radius at infinity ``rho_inf`` = 0.9 by default) instead of resolved, and
          their effect on the in-band motion is outside the estimate; pass a larger ``band=``
          to resolve them. Rigid mechanisms: the estimate sees every motion.

        docs/integrators.md says what the default does, what it was measured against, and when
        to change it.

        ``initial``: start from these poses (e.g. a StaticResult) at rest instead of the
        modelled initial state. ``callback(t, i)`` is called at each output; return True to
        stop (the result then ends at that output, ``interrupted`` True). Ctrl-C, or SIGTERM (a batch system's time limit), stops the run and returns what
        was computed (``interrupted`` = True). A solver failure raises ``phmech.SolverError``
        whose ``result`` attribute holds the trajectory computed up to the failure. ``record``:
        bodies, links (all their nodes) or frames whose poses and twists are stored (default:
        every carrier); energies, joints and ports are always stored. ``progress``: a progress
        line on stderr (simulated time, elapsed, ETA, steps and steps per second).
        ``checkpoint``: a file path; the result so far is written there (netCDF, atomically;
        ``phmech.load_result`` reads it) at the first output after every ``checkpoint_every``
        seconds of wall-clock time (default 60; 0: every output), and the final (or partial,
        on failure) result at the end (phmech._run.Checkpoint, docs/user_guide.md). A
        ``phmech.CostWarning`` is issued when the steps are far smaller than the band needs and
        the run is on course to take long (it says why and what to do).

        Limits: both integrators take at most 10^6 steps between two output times (a run whose
        ``max_step``, ``step`` or ``band`` already implies more raises ModelError at once, any
        other SolverError), and the outputs may take at most half the machine's memory. No
        result holds a NaN or inf: a non-finite value (the model's numbers overflowing double
        precision) raises SolverError with the finite part of the trajectory.

        ``result.stats`` reports what the run cost and how good it is: steps, evaluations
        (``residual_evals``, ``jacobian_evals``: iteration-matrix refreshes, ``nonlinear_iters``:
        Newton iterations, ``newton_iters_per_step``), wall time, ``band`` [Hz; None where
        no band applies: IDA, the tree integrator, a fixed ``step``]; adaptive
        generalized-alpha only: ``error_estimate`` (the sum of the local error estimates of the
        configuration, max norm: a bound without error propagation), ``error_ratio`` (the
        largest local estimate of an accepted step over its tolerance, per unit step: <= 1
        keeps the contract) and ``error_ratio_time`` [s] (when that step ended), ``floor_steps``
        (steps accepted above the tolerance at the refinement's limit; with error_sum > 1
        they warn),
        ``noise_steps`` (steps accepted above the tolerance per unit step where a shorter step
        did not lower the estimate, in a rigid mechanism, or the estimate was within Newton's
        tolerance: docs/user_guide.md, "Accuracy contract"), ``error_sum`` (the accepted steps'
        local estimates summed, in tolerances: above 1 the errors of the noise-accepted steps
        may have added up beyond rtol, and an AccuracyWarning says so), ``error_sum_max`` (each
        step's largest configuration state's estimate in its own tolerance, summed: above 6, in
        a run without a global error estimate, an AccuracyWarning), ``newton_rtol``
        (Newton's relative tolerance at the end: 1e-7, or min(rtol, 1e-7), tightened 10x at a
        time down to 1e-11 while error_sum runs ahead of its share of the tolerance, in a run on
        course for at most 3e5 steps), ``global_error_estimate`` (in a rigid mechanism: the
        local estimates carried along the linearized motion, the largest over the run of a
        configuration state's error over rtol times its largest magnitude plus atol, in
        tolerances: above 1 an
        AccuracyWarning says so; None with flexible links, where it is not estimated),
        ``global_error_time`` [s] (when), ``global_error_state`` (which coordinate, in words),
        ``global_error_absolute``, ``global_error_tolerance`` and ``global_error_scale`` (that
        coordinate's estimated error, its tolerance and its largest size over the run so far,
        in its units), ``global_error_stiff_blocks`` (how many of the
        blocks of 8 steps the estimate propagates at once were stiff -- a stiff force element
        damping within a block, a singular configuration -- each carried unchanged and followed
        by 64 steps propagated one by one), ``min_step`` [s] (the shortest step); and ``energy_scale`` [J], ``ledger_relative`` (the largest absolute
        energy ledger residual / energy_scale; above 4e-3 an AccuracyWarning), ``numerical_dissipation``
        [J] (energy the integrator removed by the end of the run, from the ledger; above 20 rtol
        of energy_scale an AccuracyWarning with the default integrator: docs/user_guide.md,
        "Energy ledger") and ``max_mu`` (the largest multiplier of the
        position constraints at the outputs, a velocity correction [m/s, rad/s] that is zero for
        the exact motion: docs/method.md section 6.2).

        Other integrators (docs/integrators.md):

        - ``integrator="generalized-alpha", step=h``: fixed step ``h`` [s] (no error estimate;
          ``rtol``/``atol``, default 1e-8 and rtol * 1e-2, are then its Newton tolerances).
          ``rho_inf`` in [0, 1] (default 0.9) is the spectral
          radius at infinity: 1 has no numerical dissipation (then stiff vibrations a step does not resolve
          are not damped and Newton may converge badly), smaller values damp what the step does
          not resolve. Steps are shortened evenly to land on the output times and the breakpoints
          of the time laws (outputs closer than ``h`` shorten the steps to their spacing); after
          the start and each breakpoint a failing first step is redone as one backward-Euler
          step.
        - ``integrator="ida"``: SUNDIALS IDA, variable-order BDF with local error control on
          ``rtol`` (default 1e-8) and ``atol``. ``error_test="all"`` (default) puts every
          differential state in the error test, so the step resolves every vibration present,
          however fast (accurate and energy-consistent, and costly when flexible links are
          excited: minutes to hours where the default takes seconds). ``"configuration"``
          leaves the twists out and needs ``max_order`` <= 2 (default 5 with "all", 2 with
          "configuration"); it controls only the poses' local error, so its global error can
          be far above ``rtol``: a rigid four-bar at rtol 1e-9 ended 8.4e-4 rad off in its
          crank angle after 2 s ("all": 2.8e-6 at order 2, 7.6e-7 at order 5). Keep it for
          flexible links whose mesh vibrations "all" would resolve. ``max_step`` [s] bounds
          the steps (IDA and adaptive generalized-alpha).
        - ``integrator="tree"``: a tree of rigid bodies in joint coordinates (O(n)
          articulated-body algorithm, explicit Dormand-Prince 5(4) with local error control on
          ``rtol`` (default 1e-8) and ``atol`` over the joint coordinates and rates). It takes
          rigid bodies each hanging as side b of one fixed, revolute, prismatic, helical or
          cylindrical pair from its parent or the ground, and refuses (ValueError naming the
          reason) beam elements, closed loops, prescribed motions, components with internal
          states and sampled controllers. Every result field is the other integrators' (the
          multipliers from each joint's wrench); ``max_step`` bounds the steps; the run is 3-D
          (``planar`` does not apply). Not for stiff models: its steps follow the fastest motion.

        ``linear_solver``: ``"auto"`` (KLU sparse for the generalized-alpha, and for IDA with 6
        or more carriers, else dense), ``"dense"`` or ``"klu"``; both factor the same
        closed-form Jacobian.

        ``planar``: when every carrier moves in one plane normal to a world axis (phmech.planar
        says what is checked, at the initial configuration), the integrator solves a DAE of the
        in-plane states alone (7 of a carrier's 13; out-of-plane constraint rows dropped), with
        the same results. None (default): so when the checks pass, with the generalized-alpha
        (IDA stays 3-D unless asked: see the comment in simulate); True: require it (ModelError
        naming the first check that fails); False: the 3-D DAE. ``result.stats["planar"]`` is
        the plane's normal axis ("x", "y", "z") or None.

        ``error_check`` (``integrator="tree"``: None is True; ``integrator="ida"`` on a rigid
        mechanism: None is False, True asks for it; others: ModelError): the tree integrator
        controls each step's local error, not the result's, and unchecked its result can be
        many times its tolerance off (a UR5 swinging 2 s: 60x in a joint rate at rtol 1e-4, 14x
        at 1e-6, 4.0x at its default 1e-8). With the check, a run at rtol/10 and atol/10
        estimates the result's error by their difference: the largest over the joint
        coordinates and rates of abs(difference) / (rtol max(abs(coordinate)) + atol),
        ``stats["global_error_estimate"]`` (``global_error_time``, ``global_error_state`` when
        and where). Above 1, that run is checked by one at a tenth of its tolerances in turn,
        up to 10 000x tighter than asked, and the first run within rtol and atol as asked is
        returned (``integration_rtol``: its rtol, ``error_check_rtol``: its check's); beyond,
        the last run, with an AccuracyWarning (a chaotic motion). The UR5: 0.14x, 0.69x and
        0.54x (estimates 0.14, 0.69, 0.35) for 2-7x the run's CPU (16, 18, 36 ms against 2.5,
        5.1, 8.1). False skips it (``stats["global_error_estimate"]`` None). IDA the same way,
        when asked: unchecked, the 170 deg pendulum of tests/test_tree.py ends 167x its
        tolerance off at rtol 1e-6 and 7360x at its default 1e-8."""
        return _simulate.simulate(self, t_end=t_end, dt_out=dt_out, rtol=rtol, atol=atol,
                                  linear_solver=linear_solver, initial=initial, t_start=t_start,
                                  callback=callback, max_step=max_step, max_order=max_order,
                                  record=record, progress=progress, error_test=error_test,
                                  integrator=integrator, step=step, rho_inf=rho_inf, band=band,
                                  checkpoint=checkpoint, checkpoint_every=checkpoint_every,
                                  planar=planar, error_check=error_check)

    def stress_resultants(self, result: SimulationResult, link: Union[str, FlexibleLink]) -> np.ndarray:
        """Section stress resultants of each element of ``link`` along a simulation, shape
        (nt, elements, 6), in the strain order (torsion, bending y, bending z [N m], axial,
        shear y, shear z [N]); see phmech.postprocess.stress_resultants."""
        lk = link_of(self._links, link, "stress_resultants")
        return postprocess.stress_resultants(self._desc, _model.build(self), result, lk)

    def constraint_residuals(self, result: SimulationResult) -> dict:
        """Position and velocity constraint residuals of EVERY pair row (redundant rows included)
        along a simulation: ``position`` (nt,) max ``|g(H)|`` [rad or m], ``velocity`` (nt,) max ``|G t|``
        [rad/s or m/s] (prescribed rates of driven pairs subtracted); see
        phmech.postprocess.constraint_residuals."""
        result = postprocess.simulation_result(result, "constraint_residuals")
        if result.carriers is not None:
            raise ModelError("constraint_residuals needs every carrier's pose: simulate without record=")
        return postprocess.constraint_residuals(self._desc, _model.build(self), result)

    def sized(self, band: Optional[float] = None, tolerance: Optional[float] = None,
              max_elements: int = 256) -> "Mechanism":
        """A copy of this mechanism, rebuilt from its add_* calls (as save/load do), whose
        nonlinear flexible links have the fewest elements with which ITS OWN modes up to ``band``
        [Hz] are within ``tolerance`` (relative) of the converged ones: supports, bodies and
        couplings included, which the per-link choice of ``Mechanism(band=...)`` cannot know
        (it sizes each link free in space, the support with the largest error).

        ``band`` and ``tolerance`` default to the Mechanism's ``band`` and
        ``frequency_tolerance``. The links' counts grow together, in proportion to how many
        wavelengths of the band each spans (phmech.mesh). A reference is refined (8, 16, 32, ...
        elements on the widest link) until it settles within ``tolerance`` / 10; then meshes
        from 1 element up are compared with it, and the first whose modes in the band are within
        ``tolerance`` (its difference plus the reference's error) is kept: the choice is
        measured, not predicted, and is the fewest on that path. Modes below 1e-3 of the band
        (rigid motions) are not compared; modes are those of ``modes()`` (the initial
        configuration). ``result.sizing`` (phmech.mesh.MechanismMeshChoice) says what was chosen
        and the error bound. This mechanism is not changed: take the new one's links, bodies and
        frames by name (``result.links["arm"]``). Raises ModelError when the mechanism cannot be
        rebuilt from its calls (save() would refuse it too), a frame sits inside a link (another
        mesh would move it) or ``max_elements`` are not enough."""
        band = self.band if band is None else band
        if band is None:
            raise ModelError("sized(): give band= (the highest frequency to resolve, Hz) or set "
                             "Mechanism(band=...)")
        tol = self.frequency_tolerance if tolerance is None else tolerance
        return mesh.size_mechanism(self, band, tol, max_elements)[0]

    def modes(self, n: int = 5, at: Optional[StaticResult] = None, time: float = 0.0,
              spin: Optional[tuple] = None) -> ModesResult:
        """The ``n`` lowest linearized modes at the initial configuration, or at a static
        equilibrium ``at``: its constraint wrenches give the geometric stiffness, and the extra
        loads it was found under (``static(loads=...)``) act as they did there. At the initial
        configuration, when it passes the equilibrium check, the modes are those of the
        equilibrium its static solve found there (within 1e-6 of it), with that equilibrium's
        constraint wrenches and stresses (a pendulum's gravity stiffness comes through them).

        Each mode is labelled (``kind``: bending-y, bending-z, torsion, axial or rigid-body, with
        energy shares and participations; phmech.analysis.label_modes, ModesResult). When the
        configuration is not a static equilibrium (a static solve from it moves it), an
        EquilibriumWarning says so: the values are then eigenvalues of the tangent stiffness,
        negative ones shown as negative frequencies.

        ``time`` [s]: the loads act as at that time. When a driven pair's law has moved by then
        (its value or rate differs from t = 0's) a ModelError names the pair and the values:
        the initial configuration holds it at s(0), and modes there would be the t = 0 ones
        (drive it with ``law.shifted(-time)`` and call modes() at time 0 instead).

        With components (``add_component``: controllers, motors, friction) the modes are the
        closed loop's (docs/method.md section 7.5): the eigenvalues s [1/s] of
        ``linearize().A`` with the components' laws linearized at rest and their states,
        one of each complex pair, the ``n`` of smallest magnitude; ``omega`` = abs(s) [rad/s]
        (natural frequency, >= 0), ``damping_ratio`` = -Re(s)/abs(s) (negative: unstable),
        ``poles`` the s themselves, ``shapes`` the eigenvectors' displacement part turned real.
        The EquilibriumWarning then checks the rest state with the components' efforts and
        state rates (``LinearPortHamiltonian.at_rest``).

        ``spin`` = (name of a Revolute pair on the ground, Omega [rad/s]): the modes about the
        steady rotation of the whole mechanism at Omega about that pair's axis (drive the pair
        with ``Linear(rate=Omega)``, or leave it free), in the frame turning with it
        (docs/method.md section 7.6): the relative equilibrium first (a static solve with the
        centrifugal wrenches, unless ``at`` gives it: ``static(spin=...)``), then the poles of
        its linearization with centrifugal stiffness and Coriolis (gyroscopic) coupling, as
        with components (``poles``; ``omega`` >= 0). Gravity must be zero or along the axis.
        ``phmech.plot.campbell`` draws the frequencies against Omega."""
        return _modes.modes(self, n, at, time, spin)

    def linearize(self, at: Optional[StaticResult] = None, inputs: Sequence = (),
                  outputs: Optional[Sequence] = None, time: float = 0.0,
                  spin: Optional[tuple] = None):
        """The linear port-Hamiltonian model (phmech.linear.LinearPortHamiltonian: J, R, Q, B,
        C, D, passivity(), to_statespace(), to_control()) about the initial configuration, or
        about a static equilibrium ``at`` (its constraint wrenches give the geometric stiffness
        and its extra loads act, as in ``modes``; at an initial configuration that passes the
        equilibrium check, about the equilibrium its static solve found there), on the constraint manifold: the reduced
        coordinates are the null space of the constraint Jacobian that ``modes`` uses, so the
        model's undamped frequencies are the modes' (docs/method.md section 7.4).

        ``inputs``: port names -- a pair with joint coordinates or an actuator (the k joint
        efforts [N m or N]), a wrench, interaction or distributed load (the value of its law:
        u = 1 applies the wrench as given), a body's name or a Frame/Body object (a wrench
        (tau [N m], f [N]) in the frame's axes at its origin). ``outputs``: None for the
        collocated outputs (the inputs' power conjugates: joint rates, the load's velocity along
        its wrench, the frame's body twist (omega, v); y^T u is the power supplied), or a list of
        port names as for inputs (their power-conjugate velocities, labelled "<pair>.rate",
        "<frame>.omega_x", ...) and sensors -- a sensor's name (``add_sensor``) or a sensor
        object (``JointSensor``, ``FrameSensor``, ``TipDeflection``, ``LinkStrain``,
        ``ComponentState``; labelled "<pair>.x" / "<pair>.rate", "<link>.tip[i]", ...): their
        changes to first order, in the sensor's units per unit state -- joint coordinates [rad or
        m], a frame's pose [-, m] and position [m], tip deflections [rad, m] and strains [1/m,
        -] over the displacements q (C = [Cd, Cq M^-1, Cz], ``Cd``), joint rates [rad/s or m/s],
        twists [rad/s, m/s] and velocities [m/s] over the rates, component states over z
        (``Cz``). A PairWrench is refused (no state), and sensors about a steady rotation
        (``spin``). The inputs perturb the loads
        acting at ``time`` (whose stiffness, e.g. of a world-fixed force on a rotating body, is
        in K); a driven pair whose law has moved by ``time`` is refused as in :meth:`modes`.
        About a configuration that is not a static equilibrium an EquilibriumWarning says so,
        as :meth:`modes` does: K is the tangent there and x = 0 is no rest state.

        With components (``add_component``) their states join the state, x = (q, p, z), and
        their laws linearized at rest at their initial states give A the closed loop
        (``Kc``, ``Dc``, ``Kz``, ``Fq``, ``Fv``, ``Fz``; ``poles()``): linear controllers,
        viscous friction and DC motors exactly, Coulomb and Stribeck friction as their slope
        at v = 0 (a damper Fc / v_reg), LuGre as its pre-sliding spring sigma0 and damper
        sigma1 + sigma2 (docs/method.md section 7.5).

        ``spin`` = (Revolute pair on the ground, Omega [rad/s]): about the steady rotation, as
        in :meth:`modes` (its relative equilibrium unless ``at`` gives it; the model's
        ``gyroscopic`` matrix and centrifugal stiffness, docs/method.md section 7.6)."""
        return _linearize.linearize(self, at=at, inputs=inputs, outputs=outputs, time=time,
                                    spin=spin)

    def static(self, loads: Sequence = (), steps: int = 10, time: float = 0.0,
               tol: float = 1e-10, start: Optional[StaticResult] = None,
               check_stability: bool = True, progress: bool = False,
               spin: Optional[tuple] = None) -> StaticResult:
        """Static equilibrium under gravity, the mechanism's wrenches at ``time`` and extra
        constant ``loads`` = [(target, wrench (tau, f), frame "world"|"body"), ...], reached in
        load increments of 1/``steps`` (halved when Newton fails, grown back after fast
        convergence); Newton tolerance ``tol`` (rad, and element lengths) on the tangent step. The
        result's ``iterations`` counts Newton iterations (tangents and factorizations).

        With ``check_stability`` (the default) the equilibrium's lowest linearized mode is
        computed (``StaticResult.lowest_omega``, ``stable``). An unstable equilibrium usually
        means the load steps jumped off the loading path (past buckling, say): the solve is
        repeated once with ten times as many steps (from the same start), and the stable
        equilibrium it finds is returned (``StaticResult.steps`` says how many were used). If it
        is still unstable (an inverted pendulum is an equilibrium, and an unstable one), a
        StabilityWarning says so. The check needs loads with a potential (gravity, springs,
        actuators on pairs, dead forces); under follower loads (body-frame wrenches), moments
        (a moment of fixed direction does path-dependent work in 3-D) or interactions the load
        stiffness is not symmetric, the check would not be valid and is skipped: ``stable`` is
        None.

        ``progress``: a progress bar (tqdm, on stderr or in Jupyter) over the load factor, with
        the Newton iterations so far. Ctrl-C stops the solve (KeyboardInterrupt).

        A failure raises SolverError with the last converged state in its ``result``. When the
        loads do work on a motion that nothing resists (a revolute turned by a constant torque, a
        slider pushed along its guide, a body held by nothing under gravity) no equilibrium
        exists: the solve stops at Newton's first failure and the message names the pair or
        part, what moves and the generalized force; the error's ``free_motions`` lists them
        (FreeMotion; docs/method.md section 7.3, "No equilibrium"). A motion nothing resists on
        which the loads do no work leaves the equilibrium not unique: one is returned.

        ``spin`` = (Revolute pair on the ground, Omega [rad/s]): the relative equilibrium of
        the steady rotation at Omega about that pair's axis (the centrifugal wrenches join the
        loads, scaled by the load steps; docs/method.md section 7.6), e.g. to pass to
        ``modes(at=..., spin=...)``."""
        return _statics.static(self, loads=loads, steps=steps, time=time, tol=tol, start=start,
                               check_stability=check_stability, progress=progress, spin=spin)


def load(path) -> Mechanism:
    """The Mechanism saved in the model file ``path`` (Mechanism.save). ModelError when the file
    is not a phmech model or has a newer schema version than this phmech reads."""
    return io.load(path, Mechanism)
