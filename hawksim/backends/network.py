"""The ANN surrogate of the UVLM: the paper's 7-500-4 network (Nguyen et al. 2020, Sec. 2.4) and its files.

Network. Inputs: the seven kinematic parameters (SI: f [Hz], angles [rad], order of
:data:`hawksim.insect.kinematics.PARAM_NAMES`), each mapped to [-1, 1] by Table 2's bounds; optionally the ascent speed
V [m/s] as an eighth input mapped by [0, 2] m/s (the speed-input network, beyond the paper). One hidden layer of
``hidden`` logistic-sigmoid units (500 in the paper); four linear outputs, L+, D+, M+, P+ (Eq. 2), trained in
standardised units (``y_mean``, ``y_std`` of the training set) and returned in physical ones.

Files. Weights in safetensors (``W1`` (hidden, n_in), ``b1`` (hidden,), ``W2`` (4, hidden), ``b2`` (4,),
``y_mean`` (4,), ``y_std`` (4,)), with the input definition (names, bounds, speed) and the provenance (command,
seed, data) as JSON in the file's metadata. No pickle anywhere: a file with other shapes, other input names,
bounds or outputs than this code's is refused with :class:`SurrogateFileError`.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np

from hawksim.backends.averages import OUTPUTS
from hawksim.insect.folder import default_insect
from hawksim.insect.kinematics import PARAM_NAMES, SPEED_RANGE, Kinematics

SPEED_BOUNDS = SPEED_RANGE
"""Bounds of the speed input [m/s]: the study's range."""
FORMAT = "hawksim-surrogate-1"
SPEED_TOL = 1e-6
"""A per-speed network answers only at its own speed (to this tolerance, m/s)."""


class SurrogateFileError(ValueError):
    """A surrogate file that cannot be used: missing, not safetensors, wrong shapes or input definition."""


@dataclass(frozen=True)
class InputDefinition:
    """Names and bounds (SI) of the network's inputs; ``speed`` is the ascent speed [m/s] of a per-speed network,
    None for the speed-input network (whose last input is 'speed')."""

    names: tuple[str, ...]
    lo: tuple[float, ...]
    hi: tuple[float, ...]
    speed: float | None

    @staticmethod
    def for_speed(speed: float | None) -> InputDefinition:
        lo, hi = default_insect().bounds_si()
        names, lo, hi = list(PARAM_NAMES), list(lo), list(hi)
        if speed is None:
            names.append("speed")
            lo.append(SPEED_BOUNDS[0])
            hi.append(SPEED_BOUNDS[1])
        return InputDefinition(tuple(names), tuple(float(v) for v in lo), tuple(float(v) for v in hi),
                               None if speed is None else float(speed))

    @property
    def n_in(self) -> int:
        return len(self.names)

    def normalise(self, x: np.ndarray) -> np.ndarray:
        """(n, n_in) SI inputs -> [-1, 1] at the bounds."""
        lo, hi = np.asarray(self.lo), np.asarray(self.hi)
        return 2.0 * (np.asarray(x, dtype=float) - lo) / (hi - lo) - 1.0

    def to_json(self) -> dict:
        return {"names": list(self.names), "lo": list(self.lo), "hi": list(self.hi), "speed": self.speed}


@dataclass(frozen=True)
class Surrogate:
    """A trained network. Arrays as in the module docstring (float64); ``meta``: provenance and scores."""

    inputs: InputDefinition
    W1: np.ndarray
    b1: np.ndarray
    W2: np.ndarray
    b2: np.ndarray
    y_mean: np.ndarray
    y_std: np.ndarray
    meta: dict = field(default_factory=dict, compare=False)

    @property
    def hidden(self) -> int:
        return self.W1.shape[0]

    def features(self, x: np.ndarray, speed: float | np.ndarray | None = None) -> np.ndarray:
        """Network inputs (n, n_in) SI from kinematics (n, 7) SI and, for the speed-input network, the speed."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        if x.shape[1] != len(PARAM_NAMES):
            raise ValueError(f"kinematics must have shape (n, {len(PARAM_NAMES)}), got {x.shape}")
        if self.inputs.speed is None:
            if speed is None:
                raise ValueError("the speed-input surrogate needs the ascent speed")
            v = np.broadcast_to(np.asarray(speed, dtype=float), (x.shape[0],))
            return np.column_stack([x, v])
        if speed is not None and np.any(np.abs(np.asarray(speed) - self.inputs.speed) > SPEED_TOL):
            raise ValueError(f"this surrogate was trained at {self.inputs.speed:g} m/s only, not {speed}")
        return x

    def predict(self, x: np.ndarray, speed: float | np.ndarray | None = None, *, dtype=np.float64,
                batch: int = 65536) -> np.ndarray:
        """(n, 4) L+, D+, M+, P+ for kinematics x (n, 7) SI (float64 numpy; see ``predict_torch`` for speed)."""
        z = self.inputs.normalise(self.features(x, speed)).astype(dtype)
        out = np.empty((z.shape[0], len(OUTPUTS)), dtype=np.float64)
        W1, b1, W2, b2 = (a.astype(dtype) for a in (self.W1, self.b1, self.W2, self.b2))
        for s in range(0, z.shape[0], batch):
            h = z[s:s + batch] @ W1.T + b1
            h = 0.5 * (1.0 + np.tanh(0.5 * h))  # logistic sigmoid, overflow-free
            out[s:s + batch] = h @ W2.T + b2
        return out * self.y_std + self.y_mean

    def _folded_float32(self):
        """W1, b1, W2, b2 (float32, transposed for addmm) with the input normalisation folded into the first layer
        and the output scaling into the second: the network applied to SI inputs, giving physical outputs."""
        lo, hi = np.asarray(self.inputs.lo), np.asarray(self.inputs.hi)
        a, c = 2.0 / (hi - lo), -2.0 * lo / (hi - lo) - 1.0  # z = a x + c
        with np.errstate(over="ignore"):  # a network that overflows gives non-finite outputs, reported by the caller
            W1, b1 = self.W1 * a, self.W1 @ c + self.b1
            W2, b2 = self.W2 * self.y_std[:, None], self.b2 * self.y_std + self.y_mean
        return tuple(np.ascontiguousarray(m, dtype=np.float32) for m in (W1.T, b1, W2.T, b2))

    def predict_torch(self, x: np.ndarray, speed: float | np.ndarray | None = None, *,
                      batch: int = 4096) -> np.ndarray:
        """As ``predict`` but evaluated by torch in float32: the batched-inference path. Normalisation and output
        scaling are folded into the weights; batches of ``batch`` samples keep the hidden layer in cache (4096:
        8 MB; ~1.8e6 samples/s on 2 cores against ~0.9e6 at 65536, scripts/benchmarks/bench_predict.py)."""
        import torch

        xs = torch.from_numpy(np.ascontiguousarray(self.features(x, speed), dtype=np.float32))
        W1T, b1, W2T, b2 = (torch.from_numpy(a) for a in self._folded_float32())
        out = torch.empty((xs.shape[0], len(OUTPUTS)), dtype=torch.float32)
        with torch.inference_mode():
            for s in range(0, xs.shape[0], batch):
                h = torch.addmm(b1, xs[s:s + batch], W1T)
                torch.sigmoid_(h)
                torch.addmm(b2, h, W2T, out=out[s:s + batch])
        return out.numpy().astype(np.float64)

    def predict_kinematics(self, kin: Kinematics, speed: float) -> dict[str, float]:
        y = self.predict(kin.as_array()[None, :], speed)[0]
        return dict(zip(OUTPUTS, (float(v) for v in y)))

    # ---------------------------------------------------------------------------------------------- files

    def save(self, path: str | Path) -> Path:
        """Write the network (safetensors) all or nothing (:func:`hawksim.atomic.write_bytes`: a full disk is an
        OSError naming the file, and leaves no half-written model file)."""
        from safetensors.numpy import save

        from hawksim.atomic import write_bytes

        tensors = {k: np.ascontiguousarray(getattr(self, k), dtype=np.float64)
                   for k in ("W1", "b1", "W2", "b2", "y_mean", "y_std")}
        meta = {"format": FORMAT, "inputs": json.dumps(self.inputs.to_json()), "outputs": json.dumps(OUTPUTS),
                "meta": json.dumps(self.meta)}
        return write_bytes(path, save(tensors, metadata=meta), "surrogate")


def load(path: str | Path, expect: InputDefinition | None = None) -> Surrogate:
    """Read a surrogate file, checking the format, shapes and input definition (against this code's Table 2
    bounds, and against ``expect`` if given)."""
    from safetensors import SafetensorError, safe_open

    from hawksim.inputfile import check_regular_file, metadata_object, strict_json

    path = check_regular_file(path, "surrogate file", SurrogateFileError)  # FIFO, directory, device: named
    try:
        with safe_open(str(path), framework="numpy") as fh:
            md = fh.metadata() or {}
            arrays = {k: fh.get_tensor(k) for k in fh.keys()}
    except (SafetensorError, OSError, ValueError) as exc:
        raise SurrogateFileError(f"{str(path)!r} is not a safetensors surrogate file: {exc}") from None
    if md.get("format") != FORMAT:
        raise SurrogateFileError(f"{str(path)!r} is not a {FORMAT} file (format {md.get('format')!r})")
    try:
        d = strict_json(md["inputs"])
        inputs = InputDefinition(tuple(d["names"]), tuple(map(float, d["lo"])), tuple(map(float, d["hi"])),
                                 None if d["speed"] is None else float(d["speed"]))
        outputs = tuple(strict_json(md["outputs"]))
    except (KeyError, TypeError, ValueError) as exc:
        raise SurrogateFileError(f"{str(path)!r} has an unreadable input definition: {exc}") from None
    try:
        meta = metadata_object(md.get("meta"), "meta")
    except ValueError as exc:
        raise SurrogateFileError(f"{str(path)!r} has unusable metadata: {exc}") from None
    if outputs != OUTPUTS:
        raise SurrogateFileError(f"{str(path)!r} predicts {outputs}, not {OUTPUTS}")
    ref = InputDefinition.for_speed(inputs.speed)
    if inputs.names != ref.names or not np.allclose(inputs.lo, ref.lo) or not np.allclose(inputs.hi, ref.hi):
        raise SurrogateFileError(f"{str(path)!r} has another input definition ({list(inputs.names)} with other "
                                 "bounds) than this hawksim's Table 2 inputs")
    if expect is not None and inputs != expect:
        raise SurrogateFileError(f"{str(path)!r} is for inputs {inputs.to_json()}, expected {expect.to_json()}")
    need = {"W1", "b1", "W2", "b2", "y_mean", "y_std"}
    if set(arrays) != need:
        raise SurrogateFileError(f"{str(path)!r} holds tensors {sorted(arrays)}, expected {sorted(need)}")
    h = arrays["b1"].shape[0] if arrays["b1"].ndim == 1 else -1
    shapes = {"W1": (h, inputs.n_in), "b1": (h,), "W2": (len(OUTPUTS), h), "b2": (len(OUTPUTS),),
              "y_mean": (len(OUTPUTS),), "y_std": (len(OUTPUTS),)}
    for k, shp in shapes.items():
        if arrays[k].shape != shp:
            raise SurrogateFileError(f"{str(path)!r}: tensor {k} has shape {arrays[k].shape}, expected {shp}")
    if not all(np.all(np.isfinite(a)) for a in arrays.values()) or np.any(arrays["y_std"] <= 0):
        raise SurrogateFileError(f"{str(path)!r} holds non-finite weights or scales")
    return Surrogate(inputs, *(arrays[k].astype(np.float64) for k in ("W1", "b1", "W2", "b2", "y_mean", "y_std")),
                     meta=meta)


# ------------------------------------------------------------------------------------------ shipped networks

SHIPPED_SPEEDS = (0.0, 0.5, 1.0, 1.5, 2.0)
"""Speeds [m/s] of the shipped per-speed networks (the paper's five)."""

NETWORKS = {"shipped": "uvlm", "reference": "uvlm_reference"}
"""Families of shipped networks (`hawksim predict --network NAME`) and their file-name stems. 'shipped': trained on
the training lattice's labels (data/uvlm_training_0.3.sqlite; the default of every command); 'reference': the
multi-fidelity networks, each a shipped network plus a correction trained on `hawksim aero`'s default-lattice labels
(data/uvlm_reference_0.1.sqlite; :mod:`hawksim.surrogate.multifidelity`, docs/surrogate.md)."""


def shipped_path(speed: float | None, network: str = "shipped") -> Path:
    """Package-data path of a shipped network of family ``network`` (:data:`NETWORKS`): per speed, or
    ``speed=None`` for the speed-input network."""
    if network not in NETWORKS:
        raise SurrogateFileError(f"no network family {network!r}; expected one of {', '.join(NETWORKS)}")
    stem = NETWORKS[network]
    name = f"{stem}_all_speeds.safetensors" if speed is None else f"{stem}_v{int(round(speed * 1000)):04d}.safetensors"
    return shipped_network(name)


def shipped_network(name: str) -> Path:
    """Path of the shipped network file ``name`` in the default insect's folder (``data/surrogates/``; checked
    against its manifest's model digest: :func:`hawksim.insect.tables.network_path`)."""
    from hawksim.insect.folder import default_insect
    from hawksim.insect.tables import network_path

    return network_path(default_insect(), f"surrogates/{name}")


@lru_cache(maxsize=16)
def _load_cached(path: str) -> Surrogate:
    return load(path)


def default_for_speed(speed: float, network: str = "shipped") -> Surrogate:
    """The shipped network of family ``network`` used at ascent speed V: the per-speed network at the five study
    speeds, the speed-input network in between."""
    for v in SHIPPED_SPEEDS:
        if abs(v - speed) <= SPEED_TOL and shipped_path(v, network).is_file():
            return _load_cached(str(shipped_path(v, network)))
    p = shipped_path(None, network)
    if not p.is_file():
        raise SurrogateFileError(f"no shipped {network} surrogate covers {speed:g} m/s (missing {p})")
    return _load_cached(str(p))


def load_for_speed(path: str | Path | None, speed: float, network: str = "shipped") -> Surrogate:
    """``--model PATH`` or the shipped network of family ``network``; a per-speed network must match the speed."""
    if path is None:
        return default_for_speed(speed, network)
    s = load(path)
    if s.inputs.speed is not None and abs(s.inputs.speed - speed) > SPEED_TOL:
        raise SurrogateFileError(f"surrogate {str(path)!r} was trained at {s.inputs.speed:g} m/s, "
                                 f"not {speed:g} m/s")
    return s
