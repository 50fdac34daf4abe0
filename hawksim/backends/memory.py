"""What an aerodynamic backend remembers between calls, and how a flight sets and reads it: the memory protocol.

The flight loop (:mod:`hawksim.flight`) never looks inside a backend. A backend's descriptor
(:class:`hawksim.backends.registry.BackendDescriptor`) names its memory kind, and a backend of that kind implements
the methods of the matching protocol below; the loop calls those and nothing else:

- :data:`MEMORYLESS`: the loads depend on the current flight state only (no method).
- :data:`PREVIOUS_CALL`: the loads depend on the previous call too (the quasi-steady added mass differences the strip
  normal velocities of two calls). A flight started from a state primes it with one call one update interval
  earlier (:class:`PrimedMemory`), so that the first loads are those of a continued flight.
- :data:`RECORD`: a record of past calls (a history network's lagged inputs, :mod:`hawksim.backends.record`) that a
  periodic orbit carries as part of its state: seeded from the orbit, read back at a beat's end, restored in a
  branch of a snapshot (:class:`RecordMemory`).
- :data:`WAKE`: state that cannot be set (the UVLM's free wake): flights from an orbit are launched earlier and
  develop it over the descriptor's ``warm_beats`` beats. No method.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol, runtime_checkable

if TYPE_CHECKING:
    import numpy as np

    from hawksim.backends.base import FlightState

MEMORYLESS = "none"
PREVIOUS_CALL = "previous-call"
RECORD = "record"
WAKE = "wake"
MEMORY_KINDS = (MEMORYLESS, PREVIOUS_CALL, RECORD, WAKE)
"""The memory kinds a descriptor may name (module docstring)."""


@runtime_checkable
class PrimedMemory(Protocol):
    """A backend of :data:`PREVIOUS_CALL` memory."""

    def prime(self, previous: FlightState) -> None:
        """After ``reset``: remember a call at ``previous`` (the flight state one update interval before the start),
        as a continuous flight would have."""


@runtime_checkable
class RecordMemory(Protocol):
    """A backend of :data:`RECORD` memory (rows (n, 6): body-axes velocity relative to the air [m/s] and angular
    velocity [rad/s], oldest first)."""

    def seed(self, record: np.ndarray, dt: float) -> None:
        """Start every flight (``reset``) with ``record`` (n, 6) as calls dt [s] apart before the start."""

    def snapshot(self, calls_per_beat: int) -> np.ndarray | None:
        """The newest records (n, 6) that a beat's inputs read at ``calls_per_beat`` calls per wingbeat; None if
        the backend keeps none."""

    def restore(self, record: np.ndarray) -> None:
        """Overwrite the values of the newest len(record) records (their times kept)."""

    def memory_beats(self) -> int:
        """Whole wingbeats the record reaches back (0: no record is read)."""
