"""Extended unsteady vortex-lattice method (UVLM): a time stepper driven by wing poses and velocities.

Method (Katz & Plotkin 2001, ch. 13; the extensions of Nguyen et al. 2016 used by the paper):

* vortex rings on each wing's flat mean surface (:mod:`aero.mesh`); no-penetration at the ring centres:
  (v_bound + v_wake + v_air - v_wing) . n = 0, where v_air is a rigid air-velocity field (:class:`FreeStream`:
  the ascent stream and the disturbance velocities of the paper's Eq. 15) and v_wing the wing's kinematic
  velocity from its pose rates; the influence matrix is built once per step and LU-solved;
* Kutta condition: every step the trailing-edge rings shed a wake row with their circulation; the wake is
  free (its corners move with the local velocity: air + induced by all vortices), in world coordinates. Where
  the trailing edge of the last bound ring row (the newest wake row's leading corners) sits is
  ``UVLMConfig.shed_rule``: a quarter panel behind the trailing edge ("ring", the default) or a fraction of the
  step's travel, ``shed_fraction`` V_te dt behind it ("travel", Katz & Plotkin Sec. 13.7/13.12);
* vortex cores that grow with age (Ramasamy & Leishman 2007; :mod:`aero.wake`);
* loads: Kutta-Joukowski on every bound segment, F = rho Gamma (V x l) with V the local flow velocity relative
  to the segment (air - wing + induced), plus the unsteady term -rho dGamma/dt A n per ring (the time
  derivative of the potential jump, phi_upper - phi_lower = -Gamma; backward difference). This vortex-force
  form is equivalent to the unsteady Bernoulli pressure integration of Katz & Plotkin Sec. 13.8 and gives the
  in-plane leading-edge suction explicitly;
* Polhamus leading-edge-suction analogy: the suction (the in-plane, forward component of the force on each
  leading-edge segment) is turned normal to the surface, on the side of the normal force (vortex lift).

Mirror symmetry: with ``mirror_plane`` the solved wings' mirror images across the plane are included by
evaluating every velocity at the target and at its mirror point, v(x) + S v(S x) (exact for symmetric motion).

Units SI; all positions, velocities and forces in the WORLD frame.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np
import scipy.linalg

from aero.biot_savart import ring_influence
from aero.lattice import Lattice, lattice_velocity, ring_lattice
from aero.mesh import WingMesh
from aero.treecode import TreeParams, lattice_tree
from aero.uvlm_config import (LEGACY_0_2, POTENTIAL_JUMPS, ROTOR_A_PRIME, SHED_RULES,  # noqa: F401 (re-exported)
                              TIME_DERIVATIVES, TREE_MIN_SEGMENTS, TREE_REPLAN_STEPS, WAKE_SUMMATIONS, UVLMConfig)
from aero.wake import Wake, lump_near_wake


def _cross(a, b) -> np.ndarray:
    """a x b over the last axis (broadcast): np.cross's formula and result, bit for bit, without its per-call
    overhead (a step makes ~13 calls on small arrays)."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    out = np.empty(np.broadcast(a, b).shape)
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


MAX_SHED_RATIO = 4.0
"""Largest allowed ratio of the wake row shed in one step (trailing-edge speed x dt) to the mean chordwise panel
length; a coarser step under-resolves the near wake."""


@dataclass(frozen=True)
class FreeStream:
    """Rigid air-velocity field, world frame: v_air(x) = v0 + omega x (x - ref) [m/s]."""

    v0: np.ndarray = field(default_factory=lambda: np.zeros(3))
    omega: np.ndarray = field(default_factory=lambda: np.zeros(3))
    ref: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self):
        for name in ("v0", "omega", "ref"):
            a = np.asarray(getattr(self, name), dtype=float)
            if a.shape != (3,) or not np.all(np.isfinite(a)):
                raise ValueError(f"FreeStream.{name} must be a finite 3-vector, got {getattr(self, name)!r}")
            object.__setattr__(self, name, a)

    def at(self, x: np.ndarray) -> np.ndarray:
        """Air velocity (..., 3) at points x (..., 3)."""
        return np.asarray(self.v0, float) + _cross(np.asarray(self.omega, float), x - np.asarray(self.ref, float))


@dataclass(frozen=True)
class StepResult:
    """Loads of one step on the solved wings (nw), world frame.

    force (nw, 3) [N]; panel_force (nw, nc, ns, 3) [N] at panel_point (ring centres) [m];
    panel_velocity (nw, nc, ns, 3) kinematic velocity of those points [m/s]; pressure (nw, nc, ns) [Pa] (the
    normal force per panel area, positive on the lower surface); gamma (nw, nc, ns) [m^2/s].
    The exact resultants use the element forces (segments at their midpoints, unsteady terms at ring centres).
    """

    force: np.ndarray
    panel_force: np.ndarray
    panel_point: np.ndarray
    panel_velocity: np.ndarray
    pressure: np.ndarray
    gamma: np.ndarray
    element_force: np.ndarray
    element_point: np.ndarray
    element_velocity: np.ndarray
    element_wing: np.ndarray

    def moment(self, ref: np.ndarray) -> np.ndarray:
        """Moment (nw, 3) of each wing's load about the point ref (3,) [N m]."""
        m = _cross(self.element_point - ref, self.element_force)
        out = np.zeros((self.force.shape[0], 3))
        np.add.at(out, self.element_wing, m)
        return out

    def moment_per_wing(self, refs: np.ndarray) -> np.ndarray:
        """Moment (nw, 3) of each wing's load about its own point refs[w] (nw, 3) [N m]."""
        m = _cross(self.element_point - refs[self.element_wing], self.element_force)
        out = np.zeros((self.force.shape[0], 3))
        np.add.at(out, self.element_wing, m)
        return out

    def power(self, v_ref=(0.0, 0.0, 0.0), omega_ref=(0.0, 0.0, 0.0), ref=(0.0, 0.0, 0.0)) -> float:
        """Power the solved wings spend on the air relative to a carrier rigid motion [W]:
        P = -sum_i F_i . (v_i - (v_ref + omega_ref x (p_i - ref)))."""
        v_c = np.asarray(v_ref, float) + _cross(np.asarray(omega_ref, float), self.element_point - np.asarray(ref))
        return float(-(self.element_force * (self.element_velocity - v_c)).sum())


def _reflect_points(x, point, normal):
    return x - 2.0 * ((x - point) @ normal)[..., None] * normal


def _reflect_vectors(v, normal):
    return v - 2.0 * (v @ normal)[..., None] * normal


class UVLM:
    """The stepper. ``meshes``: one WingMesh per solved wing (wing frames)."""

    def __init__(self, meshes: Sequence[WingMesh], config: UVLMConfig = UVLMConfig()):
        if not meshes:
            raise ValueError("UVLM needs at least one wing mesh")
        self.meshes = list(meshes)
        self.config = config
        self.wakes = [Wake(m.shape[1]) for m in self.meshes]
        self.step_count = 0
        self._gamma_prev: list[np.ndarray] | None = None  # ring circulations of the previous step
        self._gamma_prev2: list[np.ndarray] | None = None  # and of the one before
        self._dt_prev: float | None = None  # the previous step's dt [s]
        self._dt_prev2: float | None = None
        self._tree_plan: tuple[int, bool] | None = None  # (step planned, tree chosen) of wake_summation="auto"
        self.mean_len = float(np.mean([m.mean_chordwise_length for m in self.meshes]))
        self.rb = config.core_fraction * self.mean_len
        self.chord = float(np.mean([m.panel_areas.sum() / np.ptp(m.vertices[..., 1]) for m in self.meshes]))

    # ---- velocities --------------------------------------------------------------------------------
    def _induced(self, targets: np.ndarray, lattices: list[Lattice], mirror, precision: str = "float64"
                 ) -> np.ndarray:
        """Velocity (n, 3) induced at targets by the lattices (and their mirror images)."""
        n = targets.shape[0]
        if not lattices or n == 0:
            return np.zeros((n, 3))
        pts = targets if mirror is None else np.concatenate([targets, _reflect_points(targets, *mirror)])
        out = lattice_velocity(pts, lattices, precision)
        if mirror is None:
            return out
        return out[:n] + _reflect_vectors(out[n:], mirror[1])

    def _tree_velocity(self, pts: np.ndarray, wake_lat: list[Lattice], mirror) -> np.ndarray | None:
        """The wake-on-wake velocities by the treecode, or None where ``UVLMConfig.wake_summation`` asks for the
        direct sum: always ("direct"), never ("tree"), or ("auto") below :data:`TREE_MIN_SEGMENTS` wake segments
        and where the tree's planned work (:func:`aero.treecode.lattice_tree`, ``plan=True``) is not below
        :data:`aero.treecode.TREE_MARGIN` of the direct sum's; that plan is made once every
        :data:`TREE_REPLAN_STEPS` steps and kept in between."""
        mode = self.config.wake_summation
        if mode == "direct" or not wake_lat:
            return None
        if mode == "auto":
            edges = sum(int(np.count_nonzero(lat.span_gamma)) + int(np.count_nonzero(lat.chord_gamma))
                        for lat in wake_lat)
            if edges < TREE_MIN_SEGMENTS:
                return None
            due = self._tree_plan is None or self.step_count - self._tree_plan[0] >= TREE_REPLAN_STEPS
            if not due and not self._tree_plan[1]:
                return None
            if due:
                v = self._induced_tree(pts, wake_lat, mirror, plan=True)
                self._tree_plan = (self.step_count, v is not None)
                return v
        return self._induced_tree(pts, wake_lat, mirror)

    def _induced_tree(self, targets: np.ndarray, lattices: list[Lattice], mirror, plan: bool = False
                      ) -> np.ndarray | None:
        """:meth:`_induced` by the treecode (:func:`aero.treecode.lattice_tree`, ``UVLMConfig.tree_theta``);
        plan: None where the tree would not be the faster."""
        n = targets.shape[0]
        pts = targets if mirror is None else np.concatenate([targets, _reflect_points(targets, *mirror)])
        out = lattice_tree(pts, lattices, TreeParams(theta=self.config.tree_theta), plan=plan)
        if mirror is None or out is None:
            return out
        return out[:n] + _reflect_vectors(out[n:], mirror[1])

    def _wake_lattices(self, r_attached: float | None = None) -> list[Lattice]:
        """Wake lattices; r_attached: core of the edges on the trailing edge (default: the bound core)."""
        c = self.config
        rw = c.wake_core_chords * self.chord
        ra = self.rb if r_attached is None else r_attached
        lats = [w.lattice(rw, c.nu, c.a_prime, c.core_growth, r_attached=ra) for w in self.wakes]
        return [lat for lat in lats if lat is not None]

    # ---- the step ----------------------------------------------------------------------------------
    def step(self, dt: float, R: np.ndarray, origin: np.ndarray, v_origin: np.ndarray, omega: np.ndarray,
             freestream: FreeStream = FreeStream(), mirror_plane=None) -> StepResult:
        """Solve at the given poses (time t), return the loads, then shed and convect the wake to t + dt.

        Args (nw = number of meshes): dt [s]; R (nw, 3, 3) wing frame -> world; origin (nw, 3) [m];
        v_origin (nw, 3) [m/s]; omega (nw, 3) [rad/s]; freestream: air velocity field;
        mirror_plane: (point (3,), unit normal (3,)) to include the wings' mirror images, or None.
        """
        nw = len(self.meshes)
        R, origin, v_origin, omega = (np.asarray(a, dtype=float) for a in (R, origin, v_origin, omega))
        for name, a, shape in (("R", R, (nw, 3, 3)), ("origin", origin, (nw, 3)), ("v_origin", v_origin, (nw, 3)),
                               ("omega", omega, (nw, 3))):
            if a.shape != shape:
                raise ValueError(f"UVLM step: {name} must have shape {shape}, got {a.shape}")
            if not np.all(np.isfinite(a)):
                raise ValueError(f"UVLM step {self.step_count}: {name} contains non-finite values")
        if not (np.isfinite(dt) and dt > 0):
            raise ValueError(f"UVLM step: dt must be a positive finite time, got {dt}")
        mirror = None
        if mirror_plane is not None:
            p0, m = (np.asarray(a, dtype=float) for a in mirror_plane)
            mirror = (p0, m / np.linalg.norm(m))
        c = self.config
        k = self.step_count

        # 1. geometry in world
        rings = [o + msh.rings @ Rw.T for msh, Rw, o in zip(self.meshes, R, origin)]
        colloc = [o + msh.collocation @ Rw.T for msh, Rw, o in zip(self.meshes, R, origin)]
        normals = [msh.normals @ Rw.T for msh, Rw in zip(self.meshes, R)]

        def v_kin(w, x):
            return v_origin[w] + _cross(omega[w], x - origin[w])

        if c.shed_rule == "travel":  # the last ring row's trailing edge at shed_fraction x the step's travel
            for w, (msh, Rw, o) in enumerate(zip(self.meshes, R, origin)):
                te_wing = o + msh.vertices[-1] @ Rw.T
                rings[w][-1] = te_wing + c.shed_fraction * dt * (freestream.at(te_wing) - v_kin(w, te_wing))

        # trailing-edge check: shed length vs panel length
        for w in range(nw):
            te = rings[w][-1]
            shed = np.linalg.norm(freestream.at(te) - v_kin(w, te), axis=-1).max() * dt
            if shed > MAX_SHED_RATIO * self.mean_len:
                raise ValueError(
                    f"UVLM step {k}: time step {dt:.3g} s too coarse: the wake row shed at the trailing edge is "
                    f"{shed / self.mean_len:.1f} chordwise panels long (limit {MAX_SHED_RATIO:g}); "
                    "use more steps per cycle or fewer chordwise panels")
            self.wakes[w].attach(te)

        # 2. right-hand side: -(v_air - v_wing + v_wake) . n
        X = np.concatenate([x.reshape(-1, 3) for x in colloc])
        N = np.concatenate([n.reshape(-1, 3) for n in normals])
        V_rel = np.concatenate([(freestream.at(x) - v_kin(w, x)).reshape(-1, 3) for w, x in enumerate(colloc)])
        wake_lat = self._wake_lattices()
        if c.near_wake_zones:  # the wing's view of the wake, lumped near the trailing edge (opt-in)
            wake_lat = [lump_near_wake(lat, np.linalg.norm(msh.vertices[-1] - msh.vertices[-2], axis=-1),
                                       self.rb * self.rb, c.near_wake_zones)
                        for lat, msh in zip(wake_lat, self.meshes)]
        v_wake = self._induced(X, wake_lat, mirror)
        rhs = -((V_rel + v_wake) * N).sum(1)

        # 3. influence matrix of the bound rings (+ images), LU solve
        corners = np.concatenate([
            np.stack([G[:-1, :-1], G[:-1, 1:], G[1:, 1:], G[1:, :-1]], axis=2).reshape(-1, 4, 3) for G in rings])
        if mirror is None:
            A = np.empty((X.shape[0], corners.shape[0]))
            ring_influence(np.ascontiguousarray(X), np.ascontiguousarray(N), np.ascontiguousarray(corners),
                           self.rb * self.rb, A)
        else:  # the collocation points and their images in one kernel call: rows n.. are the images' influence
            n = X.shape[0]
            AA = np.empty((2 * n, corners.shape[0]))
            ring_influence(np.concatenate([X, _reflect_points(X, *mirror)]),
                           np.concatenate([N, _reflect_vectors(N, mirror[1])]), np.ascontiguousarray(corners),
                           self.rb * self.rb, AA)
            A = AA[:n] + AA[n:]
        gamma_all = scipy.linalg.lu_solve(scipy.linalg.lu_factor(A, check_finite=False), rhs, check_finite=False)
        if not np.all(np.isfinite(gamma_all)):
            raise FloatingPointError(f"UVLM blow-up at step {k}: non-finite circulation (singular influence "
                                     "matrix or non-finite wake)")
        shapes = [msh.shape for msh in self.meshes]
        splits = np.cumsum([a * b for a, b in shapes])[:-1]
        gammas = [g.reshape(s) for g, s in zip(np.split(gamma_all, splits), shapes)]

        # 4. loads
        bound_lat = [ring_lattice(G, g, self.rb * self.rb, self.rb * self.rb) for G, g in zip(rings, gammas)]
        result = self._loads(dt, colloc, normals, gammas, bound_lat, wake_lat, freestream, v_kin, mirror)
        if not (np.all(np.isfinite(result.element_force))):
            raise FloatingPointError(f"UVLM blow-up at step {k}: non-finite loads")
        self._gamma_prev2, self._dt_prev2 = self._gamma_prev, self._dt_prev
        self._gamma_prev, self._dt_prev = [g.copy() for g in gammas], dt

        # 5. shed and convect
        for w in range(nw):
            self.wakes[w].shed(rings[w][-1], gammas[w][-1])
            if c.max_wake_rows is not None:
                self.wakes[w].truncate(c.max_wake_rows)
        self._convect(dt, rings, gammas, freestream, mirror)
        self.step_count += 1
        return result

    def _jump_rate(self, w: int, g: np.ndarray) -> np.ndarray:
        """d(potential jump)/dt [m^2/s^2] of wing w's panels (nc, ns) from its ring circulations g now and at the
        previous steps (``UVLMConfig.time_derivative``: "bdf2", the second-order backward difference on the
        last three steps, with unequal steps allowed; "euler" and the second step, the first-order one; zero at
        the first step). ``UVLMConfig.potential_jump`` "panel": a panel's jump is the mean of the two rings that
        bound it chordwise (ring i's circulation is the jump at the panel edge between panels i and i + 1 of the
        1/4-3/4 lattice, zero ahead of the leading edge), so that the sum over panels is the trapezoid rule of
        the jump over the plate; "ring" (hawksim 0.2): ring i's own circulation over panel i, a right-endpoint
        sum that counts a quarter ring behind the trailing edge and overstates the term by half a panel of the
        trailing edge's jump (first order in the chordwise panel; docs/validation.md)."""
        if self._gamma_prev is None:
            return np.zeros_like(g)
        g1 = self._gamma_prev[w]
        if self.config.time_derivative == "bdf2" and self._gamma_prev2 is not None:
            g2 = self._gamma_prev2[w]
            h1, h2 = self._dt_prev, self._dt_prev2  # t - t1 and t1 - t2 (a step's dt leads to the next pose)
            rate = ((2 * h1 + h2) / (h1 * (h1 + h2)) * g - (h1 + h2) / (h1 * h2) * g1
                    + h1 / (h2 * (h1 + h2)) * g2)
        else:
            rate = (g - g1) / self._dt_prev
        if self.config.potential_jump == "panel":
            rate = 0.5 * (rate + np.concatenate([np.zeros_like(rate[:1]), rate[:-1]]))
        return rate

    def _loads(self, dt, colloc, normals, gammas, bound_lat, wake_lat, freestream, v_kin, mirror
               ) -> StepResult:
        c = self.config
        # force-carrying segments: every bound edge but the trailing-edge row
        parts = [lat.segments(skip_last_row=True) for lat in bound_lat]
        mids = np.concatenate([0.5 * (p.a + p.b) for p in parts])
        v_ind = self._induced(mids, bound_lat + wake_lat, mirror)
        F_list, P_list, V_list, W_list = [], [], [], []
        panel_force, pressure = [], []
        off = 0
        for w, (p, g) in enumerate(zip(parts, gammas)):
            nc, ns = g.shape
            mid = 0.5 * (p.a + p.b)
            vk = v_kin(w, mid)
            V = freestream.at(mid) - vk + v_ind[off:off + mid.shape[0]]
            off += mid.shape[0]
            lvec = p.b - p.a
            F = c.rho * p.gamma[:, None] * _cross(V, lvec)
            n_span = nc * ns  # spanwise (leading) edges of rows 0..nc-1, row-major
            n_ring = normals[w]
            if c.le_suction:
                # leading-edge row: spanwise edges 0..ns-1; suction = forward in-plane component
                le = slice(0, ns)
                e_f = _cross(lvec[le], n_ring[0])
                e_f /= np.linalg.norm(e_f, axis=1, keepdims=True)
                s = (F[le] * e_f).sum(1)
                s_pos = np.maximum(s, 0.0)
                side = np.sign((F[le] * n_ring[0]).sum(1))
                F[le] += (-s_pos)[:, None] * e_f + (s_pos * side)[:, None] * n_ring[0]
            # unsteady term per ring
            area = self.meshes[w].panel_areas
            F_u = (-c.rho * self._jump_rate(w, g) * area)[..., None] * n_ring
            # panel assignment: leading spanwise edge -> its ring; chordwise edges split between neighbours
            pf = F_u.copy()
            pf += F[:n_span].reshape(nc, ns, 3)
            Fc = F[n_span:].reshape(nc, ns + 1, 3)
            pf[:, :-1] += 0.5 * Fc[:, 1:-1]
            pf[:, 1:] += 0.5 * Fc[:, 1:-1]
            pf[:, 0] += Fc[:, 0]
            pf[:, -1] += Fc[:, -1]
            panel_force.append(pf)
            pressure.append((pf * n_ring).sum(-1) / area)
            F_list += [F, F_u.reshape(-1, 3)]
            P_list += [mid, colloc[w].reshape(-1, 3)]
            V_list += [vk, v_kin(w, colloc[w].reshape(-1, 3))]
            W_list += [np.full(F.shape[0] + nc * ns, w)]
        ef = np.concatenate(F_list)
        ew = np.concatenate(W_list)
        force = np.zeros((len(gammas), 3))
        np.add.at(force, ew, ef)
        return StepResult(
            force=force, panel_force=np.stack(panel_force), panel_point=np.stack(colloc),
            panel_velocity=np.stack([v_kin(w, colloc[w]) for w in range(len(gammas))]),
            pressure=np.stack(pressure), gamma=np.stack(gammas), element_force=ef,
            element_point=np.concatenate(P_list), element_velocity=np.concatenate(V_list), element_wing=ew)

    def _convect(self, dt, rings, gammas, freestream, mirror) -> None:
        c = self.config
        movable = [w.vertices[1:].reshape(-1, 3) for w in self.wakes]
        pts = np.concatenate(movable)
        if pts.shape[0] == 0:
            return
        v = freestream.at(pts)
        if c.free_wake:
            rcv = c.convection_core_chords * self.chord
            bound = [ring_lattice(G, g, rcv * rcv, rcv * rcv) for G, g in zip(rings, gammas)]
            wake_lat = self._wake_lattices(r_attached=rcv)
            if c.free_wake_age is None:
                v = v + self._free_velocity(pts, bound, wake_lat, mirror)
            else:  # the young corners free, the old ones drift (a prescribed far wake)
                age = np.concatenate([np.repeat(w.age[1:], w.vertices.shape[1]) for w in self.wakes])
                young = age <= c.free_wake_age
                v[~young] += np.asarray(c.far_wake_drift, dtype=float)
                if np.any(young):
                    v[young] += self._free_velocity(pts[young], bound, wake_lat, mirror)
        if not np.all(np.isfinite(v)):
            raise FloatingPointError(f"UVLM blow-up at step {self.step_count}: non-finite wake velocity")
        off = 0
        for w in self.wakes:
            n = w.vertices[1:].reshape(-1, 3).shape[0]
            w.vertices[1:] += (v[off:off + n] * dt).reshape(w.vertices[1:].shape)
            w.age += dt
            w.age[0] = 0.0
            off += n

    def _free_velocity(self, pts, bound, wake_lat, mirror) -> np.ndarray:
        """The velocity the wings (``bound``) and the wake (``wake_lat``) induce at ``pts`` (n, 3) [m/s], the wake's
        share summed as :attr:`UVLMConfig.wake_summation` and :attr:`UVLMConfig.wake_precision` say."""
        v_tree = self._tree_velocity(pts, wake_lat, mirror)
        if v_tree is not None:  # wake on wake by the treecode, the wings' share direct
            return self._induced(pts, bound, mirror) + v_tree
        if self.config.wake_precision == "float64":
            return self._induced(pts, bound + wake_lat, mirror)
        # wake on wake in the given precision, the wings' share in float64
        return self._induced(pts, bound, mirror) + self._induced(pts, wake_lat, mirror, self.config.wake_precision)

    @property
    def wake(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """Per solved wing: (corner grid (rows+1, ns+1, 3) [m], ring circulations (rows, ns) [m^2/s])."""
        return [(w.vertices.copy(), w.gamma.copy()) for w in self.wakes]


@dataclass(frozen=True)
class RunResult:
    """A prescribed-motion run: times (nt,) [s]; force (nt, nw, 3) [N]; moment (nt, nw, 3) about each wing's
    origin [N m]; power (nt,) [W] of the solved wings relative to still (world-fixed) axes; gamma
    (nt, nw, nc, ns) [m^2/s]; all world frame."""

    times: np.ndarray
    force: np.ndarray
    moment: np.ndarray
    power: np.ndarray
    gamma: np.ndarray


def run_prescribed(meshes, config, times, R, origin, v_origin, omega, freestream: FreeStream = FreeStream(),
                   mirror_plane=None, progress=None) -> RunResult:
    """Run the UVLM over a prescribed motion sampled at ``times`` (nt,) (R (nt, nw, 3, 3), origin, v_origin,
    omega (nt, nw, 3), world). The step k uses dt = times[k+1] - times[k] (the last step repeats the previous
    dt). Inputs are checked before the first step: non-finite values and a time step too coarse for the
    wake spacing raise ValueError."""
    times = np.asarray(times, dtype=float)
    R, origin, v_origin, omega = (np.asarray(a, dtype=float) for a in (R, origin, v_origin, omega))
    nt = times.size
    for name, a in (("times", times), ("R", R), ("origin", origin), ("v_origin", v_origin), ("omega", omega)):
        if not np.all(np.isfinite(a)):
            raise ValueError(f"run_prescribed: {name} contains non-finite values")
    if nt < 2 or np.any(np.diff(times) <= 0):
        raise ValueError("run_prescribed: times must be increasing with at least two samples")
    dts = np.append(np.diff(times), times[-1] - times[-2])
    solver = UVLM(meshes, config)
    # wake-spacing check for every step before running
    for w, msh in enumerate(solver.meshes):
        te_local = msh.rings[-1]
        te = origin[:, w, None, :] + np.einsum("tij,sj->tsi", R[:, w], te_local)
        v_te = v_origin[:, w, None, :] + _cross(omega[:, w, None, :], te - origin[:, w, None, :])
        shed = np.linalg.norm(freestream.at(te) - v_te, axis=-1).max(axis=1) * dts
        worst = int(np.argmax(shed))
        if shed[worst] > MAX_SHED_RATIO * solver.mean_len:
            raise ValueError(f"time step too coarse at step {worst}: the wake row shed is "
                             f"{shed[worst] / solver.mean_len:.1f} chordwise panels long (limit {MAX_SHED_RATIO:g})")
    nw = len(solver.meshes)
    force, moment, power, gamma = np.zeros((nt, nw, 3)), np.zeros((nt, nw, 3)), np.zeros(nt), []
    for k in range(nt):
        r = solver.step(dts[k], R[k], origin[k], v_origin[k], omega[k], freestream, mirror_plane)
        force[k], moment[k], power[k] = r.force, r.moment_per_wing(origin[k]), r.power()
        gamma.append(r.gamma)
        if progress is not None:
            progress(k + 1, nt)
    return RunResult(times, force, moment, power, np.stack(gamma))
