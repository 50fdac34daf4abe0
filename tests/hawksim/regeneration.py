"""The mark of tests that compare against artefacts computed with hawksim 0.2's UVLM (issue 48 changed its unsteady
load term and shedding rule; issue 49 regenerates every shipped artefact once, on the converged UVLM and the sourced
morphology). Strict: once the artefacts are regenerated the test passes, the mark fails it, and it must go."""

import pytest

WAITS_FOR_REGENERATION = pytest.mark.xfail(
    strict=True,
    reason="waits for issue 49's regeneration: the shipped artefact was computed with hawksim 0.2's UVLM "
           "(aero.uvlm.LEGACY_0_2), which issue 48 replaced")


REGRESSED_ON_THE_SOURCED_HAWKMOTH = pytest.mark.xfail(
    strict=True,
    reason="measured regression of the per-step surrogate's LQR on hawksim 0.3's sourced hawkmoth (docs/results.md, "
           "'What got worse'): passed on hawksim 0.2's; strict, so the mark must go once it passes again")
"""The mark of slow tests of the per-step surrogate under control that passed on hawksim 0.2's hawkmoth and fail on the
sourced one (measured 2026-12-07: the perturbed start departs or does not recover at 0, 0.5, 1.5, 2 m/s per beat,
the one-beat-delay starts at every speed, the hover half-stroke gust, both ascent profiles). Not a tolerance: the
controller's region of attraction shrank (theta0 joined the design; the orbits' multipliers grew); left for the
issue that fixes it."""
