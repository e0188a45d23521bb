"""map_sequence(..., progress=callback): the job's stage events as seqtopo.ProgressEvent, and the tqdm adapter."""

import io
import sys

import numpy as np
import pytest

import seqtopo
from conftest import SOURCE_DIR, route_descriptors


def _events(path, **kwargs):
    events = []
    run = seqtopo.map_sequence(path, progress=events.append, **kwargs)
    return run, events


def _check_stages(events):
    assert all(isinstance(e, seqtopo.ProgressEvent) for e in events)
    plan = events[0]
    assert plan.kind == "plan" and plan.stage == 0 and plan.stages >= 1, plan
    begins = [e for e in events if e.kind == "begin"]
    ends = [e for e in events if e.kind == "end"]
    # Stages numbered from 1 in order, each begun and ended once, each end with its time.
    assert [e.stage for e in begins] == list(range(1, len(begins) + 1))
    assert [(e.stage, e.name) for e in ends] == [(e.stage, e.name) for e in begins]
    assert all(e.stages == plan.stages and e.name for e in begins)
    assert all(e.seconds >= 0 for e in ends)
    for e in events:
        if e.kind == "advance":
            assert 0 <= e.done and (e.total == 0 or e.done <= e.total) and e.unit, e


def test_events_of_a_map_from_arrays():
    run, events = _events(route_descriptors())
    _check_stages(events)
    assert run.map.labels.shape == (116,)
    # The same map as without a callback.
    assert np.array_equal(run.map.labels, seqtopo.map_sequence(route_descriptors()).map.labels)


def test_events_of_a_map_from_an_image_folder_count_the_work():
    run, events = _events(str(SOURCE_DIR / "data" / "rtabmap-corridor"))
    _check_stages(events)
    advances = [e for e in events if e.kind == "advance" and e.total]
    assert advances, [(e.kind, e.name) for e in events]
    assert max(e.done for e in advances) == max(e.total for e in advances)
    assert run.map.labels.shape == (84,)


def test_an_exception_in_the_callback_is_raised_when_the_job_returns():
    calls = []

    def failing(event):
        calls.append(event)
        raise KeyError("stop here")

    with pytest.raises(KeyError, match="stop here"):
        seqtopo.map_sequence(route_descriptors(), progress=failing)
    assert len(calls) == 1  # later events are dropped


def test_a_progress_that_is_not_callable_is_refused():
    with pytest.raises(TypeError, match="progress: must be a callable"):
        seqtopo.map_sequence(route_descriptors(), progress=3)


def test_tqdm_adapter_draws_one_bar_per_stage():
    pytest.importorskip("tqdm")  # Debian python3-tqdm, installed by scripts/setup.sh --test
    out = io.StringIO()
    seqtopo.map_sequence(str(SOURCE_DIR / "data" / "rtabmap-corridor"), progress=seqtopo.TqdmProgress(file=out))
    text = out.getvalue()
    assert "[1/" in text and "similarity" in text, text[-2000:]


def test_tqdm_adapter_without_tqdm_says_what_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "tqdm", None)  # import tqdm now raises ImportError
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    with pytest.raises(ImportError, match="python3-tqdm"):
        seqtopo.TqdmProgress()
