"""The GIL is released during long computations; arrays cross the boundary without needless copies."""

import threading
import time

import numpy as np
import pytest

import seqtopo
from conftest import route_descriptors


def ticks_during(call):
    """Runs call() while a Python thread records timestamps; returns (timestamps inside the middle of
    the call, call duration)."""
    stamps = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            stamps.append(time.perf_counter())
            time.sleep(0.001)

    thread = threading.Thread(target=ticker)
    thread.start()
    try:
        time.sleep(0.05)
        start = time.perf_counter()
        call()
        end = time.perf_counter()
    finally:
        stop.set()
        thread.join()
    duration = end - start
    middle = [t for t in stamps if start + 0.25 * duration < t < end - 0.25 * duration]
    return middle, duration


def test_align_releases_the_gil():
    rng = np.random.default_rng(0)
    s = rng.standard_normal((1500, 1500)).astype(np.float32) - 0.2
    middle, duration = ticks_during(
        lambda: seqtopo.align(s, reverse=False, threshold=10.0, max_alignments=30, threads=1))
    assert duration > 0.05, "the alignment was too short to tell"
    # With the GIL held the ticker could not run a single statement during the call.
    assert len(middle) >= 3, (len(middle), duration)


@pytest.mark.parametrize("work", ["build_map", "localize", "similarity"])
def test_other_long_calls_release_the_gil(work):
    rng = np.random.default_rng(1)
    if work == "similarity":
        d = rng.random((1500, 256), dtype=np.float32)
        call = lambda: seqtopo.similarity(d, threads=1)  # noqa: E731
    else:
        s = rng.standard_normal((1600, 1600)).astype(np.float32)
        call = (lambda: seqtopo.build_map(s, threads=1)) if work == "build_map" else (lambda: seqtopo.localize(s))
    middle, duration = ticks_during(call)
    assert duration > 0.05, "the computation was too short to tell"
    assert len(middle) >= 3, (len(middle), duration)


def test_float32_c_contiguous_input_is_read_in_place():
    s = np.ascontiguousarray(np.random.default_rng(2).random((30, 40), dtype=np.float32))
    view = seqtopo._core.engine_input(s)
    assert view is s or (np.shares_memory(view, s) and view.ctypes.data == s.ctypes.data)
    # Another dtype or layout is converted once (the engine never reads strided or float64 memory).
    assert not np.shares_memory(seqtopo._core.engine_input(s.astype(np.float64)), s)
    strided = s[:, ::2]
    converted = seqtopo._core.engine_input(strided)
    assert not np.shares_memory(converted, s) and np.array_equal(converted, strided)
    fortran = np.asfortranarray(s)
    assert not np.shares_memory(seqtopo._core.engine_input(fortran), fortran)


def test_any_layout_gives_the_same_alignments():
    s = seqtopo.similarity(route_descriptors()).similarity
    reference = seqtopo.align(s, gap=1.0)
    assert reference
    assert seqtopo.align(s.astype(np.float64), gap=1.0) == reference
    assert seqtopo.align(np.asfortranarray(s), gap=1.0) == reference
    assert seqtopo.align(s.tolist(), gap=1.0) == reference
    wide = np.zeros((s.shape[0], 2 * s.shape[1]), dtype=np.float32)
    wide[:, ::2] = s
    assert seqtopo.align(wide[:, ::2], gap=1.0) == reference


def test_results_own_their_buffers():
    s = seqtopo.similarity(route_descriptors()).similarity
    result = seqtopo.build_map(s)
    for array in (result.scores, result.labels, result.loop_closures, result.loop_closure_scores, result.edges):
        assert not np.shares_memory(array, s)
        assert array.flags.c_contiguous and array.flags.writeable
    assert result.scores.dtype == np.float32 and result.scores.shape == s.shape
    # Moved out of the library, not copied: the array's base is the capsule that frees the C++ vector.
    assert type(result.scores.base).__name__ == "PyCapsule"
    assert result.labels.dtype == np.int32 and result.labels.shape == (s.shape[0],)
    assert result.loop_closures.dtype == np.int64 and result.loop_closures.shape[1] == 2
    assert all(a.pairs.dtype == np.int64 and a.pairs.shape[1] == 2 for a in result.alignments)
    # The arrays outlive the result object and everything else.
    scores = result.scores
    del result
    assert np.isfinite(scores).all()
    # Inputs are never modified.
    before = s.copy()
    seqtopo.build_map(s)
    seqtopo.align(s)
    seqtopo.localize(s)
    assert np.array_equal(s, before)


def test_alignment_fields_are_consistent():
    s = seqtopo.similarity(route_descriptors()).similarity
    for a in seqtopo.align(s, self=True, min_separation=5, gap=1.0, threshold=2.0):
        assert a.score >= 2.0
        i, j = a.pairs[:, 0], a.pairs[:, 1]
        assert np.all(i - j >= 5)
        assert a.a_begin == i.min() and a.a_end == i.max() + 1
        assert a.b_begin == j.min() and a.b_end == j.max() + 1
        assert np.all(np.diff(i) > 0)
        step = np.diff(j)
        assert np.all(step > 0) if a.direction == "forward" else np.all(step < 0)
