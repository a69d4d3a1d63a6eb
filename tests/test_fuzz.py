"""Hostile files: a few hundred mutated and hand-made inputs per loader end in a result or
one clean error line (no traceback, no hang). ``bench/fuzz_loaders.py`` runs 10,000+."""

from __future__ import annotations

import os
import warnings

import pytest
from fuzz_inputs import TARGETS, run

COUNT = int(os.environ.get("GAITLAB_FUZZ", "300"))


@pytest.mark.parametrize("target", TARGETS)
def test_loader_survives_hostile_files(target: str) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # overflow in a clip the loader then refuses
        result = run(target, COUNT, seed=1)
    assert result.total == COUNT
    assert not result.crashes, f"{len(result.crashes)} crashes, first:\n{result.crashes[0][1]}"
    assert not result.hangs, f"{len(result.hangs)} inputs took over 2 s, first: {result.hangs[0][0][:200]!r}"
    assert not result.bad_messages, f"messages that are not one short line: {result.bad_messages[0][1][:300]}"
    assert result.loaded > 0 and result.clean_errors > 0  # the mutations both keep and break files
