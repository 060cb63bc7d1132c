"""The whole build of random valid designs of every cam type and follower (hypothesis).

For each kind of ``tests/valid_designs.py`` (every cam type with every follower it drives), a
few random but ordinary designs are built with ``camfab build`` in a child under a limit of CPU
time, and the contract is asserted:

- no internal error (no traceback, no crash, no runaway past the CPU limit);
- a refusal (exit 2) is one line ``FILE:LINE: field: problem``;
- the ``verification`` check passes wherever the loader accepts the design: the files hold it
  within ``manufacturing.tolerance``. A design the checks declare unbuildable has its
  verification not applicable (or held to the cam camfab computes instead), never failed.

The examples are fixed (``derandomize``) and few, to fit the suite's time; a failing design is
printed whole, as its YAML. ``scripts/random_builds.py`` runs the same designs by the thousand.
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, Phase, given, note, settings
from hypothesis import strategies as st

from camfab.errors import CamfabError
from camfab.pipeline import design_from_text
from tests.valid_designs import KINDS, HypothesisDraw, design, design_of_seed
from tests.whole_builds import build_design, dump

#: Designs built per kind: 27 kinds, some 60–90 s on two cores in all.
EXAMPLES_PER_KIND = 2

WHOLE_BUILD = settings(
    max_examples=EXAMPLES_PER_KIND, derandomize=True, database=None, deadline=None,
    print_blob=True, phases=(Phase.explicit, Phase.generate),
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


@pytest.mark.parametrize("kind", KINDS)
@settings(WHOLE_BUILD)
@given(data=st.data())
def test_random_valid_designs_build_verified(kind: str, data: st.DataObject) -> None:
    _, design_data = design(HypothesisDraw(data.draw), kind)
    text = dump(design_data)
    note(f"design.yaml:\n{text}")
    outcome = build_design(text)
    assert outcome.internal_error is None, f"internal error: {outcome.internal_error}"
    assert outcome.unlocated_refusal("design.yaml") is None, outcome.unlocated_refusal(
        "design.yaml")
    if outcome.code == 2:
        return
    check = outcome.verification
    assert check is not None, "the report has no verification check"
    assert check["ok"] is not False, (
        f"verification failed ({outcome.ratio:.3g}× the tolerance; other failed checks: "
        f"{', '.join(outcome.failed_checks) or 'none'}): {check['message']}")


@pytest.mark.parametrize("kind", KINDS)
def test_random_valid_designs_are_mostly_accepted(kind: str) -> None:
    """The generator's designs are valid: the loader accepts at least three of four (a refusal
    is an ordinary first try, but a generator whose designs it refuses tests nothing)."""
    refused = []
    for seed in range(4):
        try:
            design_from_text(dump(design_of_seed(seed, kind)[1]), "design.yaml")
        except CamfabError as exc:
            refused.append(f"seed {seed}: {exc}")
    assert len(refused) <= 1, "the loader refuses:\n" + "\n".join(refused)
