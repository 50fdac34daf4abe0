"""Classical 2D unsteady thin-airfoil theory: the references the UVLM is validated against.

A flat plate of chord c = 2 b (b the semichord) in incompressible potential flow at speed U, small motions, a
planar wake (linear theory). Conventions here: heave h positive UP [m], pitch alpha positive NOSE UP [rad] about
the axis at x = a b behind mid-chord (a = -1/2: the quarter chord), lift positive up, reduced frequency
k = omega b / U (on the semichord), reduced time s = U t / b (semichords travelled). Coefficients on the chord:
C_L = L' / (rho U^2 b), C_T = T' / (rho U^2 b) with L', T' per unit span.

* Theodorsen's function (Theodorsen 1935, NACA Rep. 496, Eq. (VIII)), in Hankel functions of the second kind:
  C(k) = H1(k) / (H1(k) + i H0(k)) = F + i G.
* Harmonic lift for h = Re(h0 e^{i omega t}), alpha = Re(alpha0 e^{i omega t}) (Theodorsen 1935; Bisplinghoff,
  Ashley & Halfman 1955, Eq. 5-311, rewritten for h up):
  L' = pi rho b^2 (-h'' + U alpha' - b a alpha'') + 2 pi rho U b C(k) [-h' + U alpha + b (1/2 - a) alpha'],
  so C_L / (h0 / b) = pi k^2 - 2 pi i k C(k) and C_L / alpha0 = pi (i k + a k^2) + 2 pi C(k) (1 + i k (1/2 - a)).
* Wagner's indicial lift (Wagner 1925) after an impulsive start to angle alpha: C_L(s) = 2 pi alpha phi(s), from
  Theodorsen's function by the Fourier-sine integral (Garrick 1938, NACA Rep. 629, Eq. 12):
  phi(s) = (2 / pi) int_0^inf F(k) / k sin(k s) dk, evaluated here as 1/2 + (2 / pi) int (F - 1/2) / k sin(k s) dk
  (the 1/2 integrates in closed form; what is left decays as k^-3). R. T. Jones' (1938, NACA Rep. 681)
  two-exponential approximation is :func:`wagner_jones`.
* Garrick's mean thrust of a plate plunging as h = h0 sin(omega t) (Garrick 1936, NACA Rep. 567, pure
  translation, leading-edge suction included): T' = pi rho b omega^2 h0^2 (F^2 + G^2), i.e.
  C_T = pi k^2 (h0 / b)^2 (F^2 + G^2).

Pure functions of nondimensional inputs; no I/O.
"""

from __future__ import annotations

import numpy as np
import scipy.integrate
import scipy.special

QUARTER_CHORD = -0.5
"""Theodorsen's a for a pitch axis on the quarter chord (x = a b behind mid-chord)."""

WAGNER_QUAD_LIMIT = 400
"""Subintervals of the Fourier integrals in :func:`wagner` (QUADPACK QAWO on [0, WAGNER_SPLIT], QAWF beyond)."""

WAGNER_LOG_SPLIT = 2.0
"""Below this k, :func:`wagner` integrates g(k) sin(k s) directly (g = (F - 1/2) / k ~ 1 / (2k) at 0); above, with
QUADPACK's sine weight (QAWO up to WAGNER_SPLIT, QAWF beyond)."""

WAGNER_EPSABS = 1e-9
"""Absolute tolerance of each Fourier integral in :func:`wagner` (QUADPACK's default 1.5e-8 relative cannot be met
in round-off at some s and it says so; phi itself is needed to 1e-6)."""

WAGNER_SPLIT = 20.0
"""Reduced frequency where :func:`wagner` passes from the finite to the infinite Fourier integral (the integrand's
log k behaviour near 0 stays in the finite part)."""


def theodorsen(k):
    """Theodorsen's function C(k) (complex, shape of k); k > 0 on the semichord. C -> 1 as k -> 0, 1/2 as k -> inf."""
    k = np.asarray(k, dtype=float)
    if np.any(~np.isfinite(k)) or np.any(k <= 0):
        raise ValueError(f"theodorsen: the reduced frequency k must be positive and finite, got {k}")
    h1 = scipy.special.hankel2(1, k)
    h0 = scipy.special.hankel2(0, k)
    return h1 / (h1 + 1j * h0)


def heave_lift(k):
    """Complex lift coefficient per unit heave amplitude over the semichord, C_L / (h0 / b), h up, lift up: the
    first harmonic is C_L(t) = Re(heave_lift(k) h0 / b e^{i omega t})."""
    k = np.asarray(k, dtype=float)
    return np.pi * k**2 - 2j * np.pi * k * theodorsen(k)


def pitch_lift(k, a: float = QUARTER_CHORD):
    """Complex lift coefficient per unit pitch amplitude [1/rad], C_L / alpha0, nose up, about x = a b."""
    k = np.asarray(k, dtype=float)
    return np.pi * (1j * k + a * k**2) + 2 * np.pi * theodorsen(k) * (1 + 1j * k * (0.5 - a))


def garrick_thrust(k, h0_over_b):
    """Garrick's mean thrust coefficient C_T = T' / (rho U^2 b) of a plate plunging with amplitude h0 (on b)."""
    c = theodorsen(k)
    return np.pi * np.asarray(k, dtype=float) ** 2 * float(h0_over_b) ** 2 * np.abs(c) ** 2


def wagner(s):
    """Wagner's function phi(s) (shape of s), s >= 0 semichords travelled: phi(0) = 1/2, phi -> 1."""
    s_arr = np.atleast_1d(np.asarray(s, dtype=float))
    if np.any(~np.isfinite(s_arr)) or np.any(s_arr < 0):
        raise ValueError(f"wagner: the reduced time s must be >= 0 and finite, got {s}")

    def g(k):
        return (theodorsen(max(k, 1e-12)).real - 0.5) / max(k, 1e-12)

    out = np.empty_like(s_arr)
    for i, si in enumerate(s_arr):
        if si == 0.0:
            out[i] = 0.5
            continue
        # g ~ 1/(2k) at 0: the product g(k) sin(k s) is smooth there, g alone is not (QAWO would fit g)
        low, _ = scipy.integrate.quad(lambda k, s_=si: g(k) * np.sin(k * s_), 0.0, WAGNER_LOG_SPLIT,
                                      limit=WAGNER_QUAD_LIMIT, epsabs=WAGNER_EPSABS)
        mid, _ = scipy.integrate.quad(g, WAGNER_LOG_SPLIT, WAGNER_SPLIT, weight="sin", wvar=si,
                                      limit=WAGNER_QUAD_LIMIT, epsabs=WAGNER_EPSABS)
        far, _ = scipy.integrate.quad(g, WAGNER_SPLIT, np.inf, weight="sin", wvar=si, limlst=WAGNER_QUAD_LIMIT,
                                      epsabs=WAGNER_EPSABS)
        out[i] = 0.5 + 2.0 / np.pi * (low + mid + far)
    return out.reshape(np.shape(s)) if np.ndim(s) else float(out[0])


def wagner_jones(s):
    """R. T. Jones' (1938) approximation of Wagner's function: 1 - 0.165 e^{-0.0455 s} - 0.335 e^{-0.3 s}."""
    s = np.asarray(s, dtype=float)
    return 1.0 - 0.165 * np.exp(-0.0455 * s) - 0.335 * np.exp(-0.3 * s)
