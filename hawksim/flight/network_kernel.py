"""The per-step surrogate's network as compiled code: the float32 MLP that the flight loop's native callback
(:mod:`hawksim.flight.native`) evaluates at each of its updates, and the vectorisable tanh it uses.

The network is a folded ensemble (:class:`hawksim.backends.step_surrogate.NativeNetwork`: K members, tanh hidden
layers, outputs summed); its weights come in one float32 buffer in the layout :func:`mlp` documents, built by
:meth:`hawksim.backends.step_surrogate.StepSurrogateBackend.native`. The arithmetic is the numpy evaluation's
(``StepSurrogateBackend.evaluate``) up to the order of the float32 sums and tanh's last bit (tested,
tests/hawksim/test_native.py).
"""

from __future__ import annotations

import numpy as np
from numba import njit

# tanh(x) ~ x P(x^2) / Q(x^2) on |x| <= 9, evaluated in float64 and rounded to float32 (a fit of this project's:
# weighted linearised least squares, iterated, on Chebyshev nodes; relative error 1.4e-8 over [0, 9], at most
# 0.75 float32 ulp from the exact tanh, measured on 400 001 points in [-12, 12] (tests/hawksim/test_native.py);
# |x| > 9 is clamped: tanh(9) rounds to 1 in float32). Vectorisable, unlike libm's tanh (4x faster in mlp).
_TANH_P = (9.99999996e-01, -1.58873168e-01, 3.14207336e-02, 7.95380265e-03, 2.26109851e-04, 1.34286684e-06,
           8.52107591e-10)
_TANH_Q = (1.0, 1.74460056e-01, -4.37589511e-02, 2.40740775e-02, 1.63135013e-03, 2.14401922e-05, 5.02563342e-08)
_P0, _P1, _P2, _P3, _P4, _P5, _P6 = _TANH_P
_Q1, _Q2, _Q3, _Q4, _Q5, _Q6 = _TANH_Q[1:]
TANH_CLAMP = 9.0


@njit(cache=True, inline="always", error_model="numpy")
def tanh32(v):
    """tanh of a float32, to within 0.75 float32 ulp (the rational fit above), as float32."""
    x = np.float64(v)
    x = TANH_CLAMP if x > TANH_CLAMP else x
    x = -TANH_CLAMP if x < -TANH_CLAMP else x
    z = x * x
    num = x * (_P0 + z * (_P1 + z * (_P2 + z * (_P3 + z * (_P4 + z * (_P5 + z * _P6))))))
    den = 1.0 + z * (_Q1 + z * (_Q2 + z * (_Q3 + z * (_Q4 + z * (_Q5 + z * _Q6)))))
    return np.float32(num / den)


@njit(cache=True, inline="always", fastmath={"reassoc", "contract", "nsz", "arcp"}, error_model="numpy")
def _rows8(c0, c1, buf, base, a, bias, out0, out1):
    """Eight consecutive outputs of one layer for both wings (c0, c1: the inputs (a,)): the rows of ``buf`` at
    base, base + a, ... base + 7 a dotted with c0 and c1, plus bias (8,), into out0, out1 (8,). Sixteen sums in one
    loop, so each input element is loaded once for eight rows (faster than one row at a time on the shipped network:
    docs/performance.md)."""
    w0, w1 = buf[base:base + a], buf[base + a:base + 2 * a]
    w2, w3 = buf[base + 2 * a:base + 3 * a], buf[base + 3 * a:base + 4 * a]
    w4, w5 = buf[base + 4 * a:base + 5 * a], buf[base + 5 * a:base + 6 * a]
    w6, w7 = buf[base + 6 * a:base + 7 * a], buf[base + 7 * a:base + 8 * a]
    z = np.float32(0.0)
    s00 = s01 = s02 = s03 = s04 = s05 = s06 = s07 = z
    s10 = s11 = s12 = s13 = s14 = s15 = s16 = s17 = z
    for i in range(a):
        u, v = c0[i], c1[i]
        s00 += u * w0[i]
        s10 += v * w0[i]
        s01 += u * w1[i]
        s11 += v * w1[i]
        s02 += u * w2[i]
        s12 += v * w2[i]
        s03 += u * w3[i]
        s13 += v * w3[i]
        s04 += u * w4[i]
        s14 += v * w4[i]
        s05 += u * w5[i]
        s15 += v * w5[i]
        s06 += u * w6[i]
        s16 += v * w6[i]
        s07 += u * w7[i]
        s17 += v * w7[i]
    out0[0], out0[1], out0[2], out0[3] = s00 + bias[0], s01 + bias[1], s02 + bias[2], s03 + bias[3]
    out0[4], out0[5], out0[6], out0[7] = s04 + bias[4], s05 + bias[5], s06 + bias[6], s07 + bias[7]
    out1[0], out1[1], out1[2], out1[3] = s10 + bias[0], s11 + bias[1], s12 + bias[2], s13 + bias[3]
    out1[4], out1[5], out1[6], out1[7] = s14 + bias[4], s15 + bias[5], s16 + bias[6], s17 + bias[7]


@njit(cache=True, fastmath={"reassoc", "contract", "nsz", "arcp"}, error_model="numpy")
def mlp(x, buf, K, n_in, h, L):
    """The folded ensemble network at inputs x (2, n_in) float32 (both wings), compiled (the flight loop's native
    callback, :mod:`hawksim.flight.native`, calls it with a :class:`NativeNetwork`'s buffer) -> (2, 6) float32:
    K members of L layers (tanh between, :func:`tanh32`), summed, plus the output bias. ``buf`` (float32, flat)
    holds, per layer l, the weights (K, b_l, a_l) (output-major: the numpy evaluation's W^T transposed, so each
    output is a contiguous dot product) then the biases (K, b_l) (a_0 = n_in, hidden b = h, last b = 6; the last
    layer's biases are the members' zeros), then the output bias (6). The arithmetic of the numpy evaluation up to
    the order of the float32 sums (``fastmath`` lets them vectorise; ~1e-7 relative) and tanh's last bit; each
    weight row is read once for both wings, and each input element once for eight rows (:func:`_rows8`): the
    shipped 3 x 192^3 network's 466 000 multiply-adds take a fraction of the time of row-major axpy sums with
    libm's tanh (docs/performance.md).
    The callback that calls it (:mod:`hawksim.flight.native`) is never loaded from the cache compiled against an
    older version of it: :mod:`aero.numba_cache` keeps one cache folder per version of the sources."""
    out = np.zeros((2, 6), np.float32)
    width = max(n_in, h)
    cur0, cur1 = np.empty(width, np.float32), np.empty(width, np.float32)
    nxt0, nxt1 = np.empty(width, np.float32), np.empty(width, np.float32)
    for k in range(K):
        for i in range(n_in):
            cur0[i] = x[0, i]
            cur1[i] = x[1, i]
        off = 0
        for lay in range(L):
            a = n_in if lay == 0 else h
            b = 6 if lay == L - 1 else h
            wbase = off + k * a * b
            off += K * a * b
            bias = buf[off + k * b:off + (k + 1) * b]
            off += K * b
            c0, c1 = cur0[:a], cur1[:a]
            j = 0
            while j + 8 <= b:  # eight outputs at a time: each input vector loaded once for 16 sums
                _rows8(c0, c1, buf, wbase + j * a, a, bias[j:j + 8], nxt0[j:j + 8], nxt1[j:j + 8])
                j += 8
            while j < b:
                w = buf[wbase + j * a:wbase + (j + 1) * a]  # a slice: its index is known in range, so it vectorises
                s0 = np.float32(0.0)
                s1 = np.float32(0.0)
                for i in range(a):
                    s0 += c0[i] * w[i]
                    s1 += c1[i] * w[i]
                nxt0[j] = s0 + bias[j]
                nxt1[j] = s1 + bias[j]
                j += 1
            if lay < L - 1:
                for j in range(b):
                    cur0[j] = tanh32(nxt0[j])
                    cur1[j] = tanh32(nxt1[j])
            else:
                for j in range(6):
                    out[0, j] += nxt0[j]
                    out[1, j] += nxt1[j]
    fb = buf.shape[0] - 6
    for j in range(6):
        out[0, j] += buf[fb + j]
        out[1, j] += buf[fb + j]
    return out
