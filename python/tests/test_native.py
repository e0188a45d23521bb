"""The module feels native (issue #22): short reprs with the counts, a namespace of exactly __all__, the whole
map job with its evaluation, odometry and report from arrays in memory, localization with ground truth and its
report, errors that say what to call instead."""

import json
import os
import types

import numpy as np
import pytest

import seqtopo
from conftest import SOURCE_DIR, localization_pair, route_descriptors

CORRIDOR = os.path.join(str(SOURCE_DIR), "data", "rtabmap-corridor")


def test_namespace_is_all_and_the_submodules():
    public = {n for n in dir(seqtopo) if not n.startswith("_")}
    assert public == set(seqtopo.__all__), sorted(public ^ set(seqtopo.__all__))
    for name in ("np", "os", "List", "Optional", "dataclasses", "annotations"):
        assert not hasattr(seqtopo, name), name
    for name in seqtopo.__all__:
        assert not isinstance(getattr(seqtopo, name), types.ModuleType), name


def test_reprs_are_short_and_have_the_counts():
    d = route_descriptors()
    s = seqtopo.similarity(d)
    m = seqtopo.build_map(s.similarity)
    for obj in (s, m, m.alignments[0], seqtopo.localize(s.similarity[:40, :]),
                seqtopo.match_strings(["vAvB", "vCvD"], ["vAvB"])[0]):
        text = repr(obj)
        assert len(text) < 200 and "\n" not in text and "array(" not in text, text
    assert repr(s) == "SimilarityResult(116 x 116, cosine, kappa %.4g (auto))" % s.kappa
    assert repr(m).startswith("MapResult(116 images, %d places, %d junctions, %d alignments"
                              % (len(m.places), len(m.junctions), len(m.alignments)))
    a = m.alignments[0]
    assert repr(a) == "Alignment(%s, score %.4g, a %d..%d, b %d..%d, %d pairs)" % (
        a.direction, a.score, a.a_begin, a.a_end - 1, a.b_begin, a.b_end - 1, len(a.pairs))


def test_build_map_on_descriptors_says_to_compute_a_similarity_first():
    d = np.random.default_rng(1).random((600, 256)).astype(np.float32)
    with pytest.raises(ValueError) as error:
        seqtopo.build_map(d)
    text = str(error.value)
    assert "600 x 256" in text and "seqtopo.similarity(descriptors).similarity" in text and "map_sequence" in text


def test_map_sequence_from_arrays_with_truth_odometry_and_report(tmp_path):
    d = route_descriptors()
    n = len(d)
    route = list(range(60)) + list(range(15, 45)) + list(range(55, 29, -1))
    positions = np.array([[p, 0.0] for p in route])
    # Cumulative odometry that agrees with the revisits (the odometry gate drops alignments it contradicts).
    odometry = np.array([[p + 0.05 * k, 0.1, 0.0] for k, p in enumerate(route)], dtype=np.float32)
    run = seqtopo.map_sequence(d, ground_truth=positions, gt_radius=1.5, odometry=odometry,
                               gt_places=route, gt_poses=np.c_[positions, np.zeros(n)])
    assert isinstance(run, seqtopo.MapRun)
    assert run.metrics["f1"] > 0.8 and run.baseline["method"], run.metrics
    assert run.topology["adjusted_rand_index"] > 0.3, run.topology
    assert set(run.trajectory_errors) == {"odometry", "ekf", "pose_graph"}
    text = repr(run)
    assert text.startswith("MapRun(memory: 116 images") and "F1 %.3f" % run.metrics["f1"] in text, text
    # The same as the command line gives for the same similarity (the truth as an image, the same matrix).
    seqtopo.write_report(run, tmp_path / "out")
    for name in ("map.json", "metrics.json", "report.html", "metric_map.png", "pr_curve.png"):
        assert (tmp_path / "out" / name).exists(), name
    metrics = json.loads((tmp_path / "out" / "metrics.json").read_text())
    assert metrics["loop_closure"]["f1"] == pytest.approx(run.metrics["f1"])
    html = (tmp_path / "out" / "report.html").read_text()
    assert "no images: the sequence was given in memory" in html and 'id="seqtopo-data"' in html


def test_array_and_file_arguments_do_not_mix():
    with pytest.raises(ValueError, match="give an array with arrays in memory"):
        seqtopo.map_sequence(route_descriptors(), ground_truth="truth.bmp")
    with pytest.raises(ValueError, match="give a file with a path input"):
        seqtopo.map_sequence(CORRIDOR, ground_truth=np.eye(84))
    with pytest.raises(ValueError, match="gt_radius"):
        seqtopo.map_sequence(route_descriptors(), ground_truth=np.zeros((116, 2)))


def test_localize_sequences_with_ground_truth_and_report(tmp_path):
    map_d, query = localization_pair()
    np.save(tmp_path / "map.npy", map_d)
    np.save(tmp_path / "query.npy", query)
    truth = [(q, q + 20) for q in range(30)]
    run = seqtopo.localize_sequences(tmp_path / "map.npy", tmp_path / "query.npy", ground_truth=truth, tolerance=2)
    assert isinstance(run, seqtopo.LocalizeRun)
    assert run.queries == 40 and run.maps == 80 and run.map.shape == (40,)
    assert run.metrics["recall_at_1"] > 0.8, run.metrics
    assert set(run.baselines) == {"single_frame", "seqslam"}
    assert abs(int(np.median(run.map[:30] - np.arange(20, 50)))) <= 2
    assert "recall@1 %.3f" % run.metrics["recall_at_1"] in repr(run) and len(repr(run)) < 250
    seqtopo.write_report(run, tmp_path / "out")
    assert (tmp_path / "out" / "matches.csv").read_text().startswith("query,map,score,confidence,e_value,in_map\n")
    assert "Localization accuracy" in (tmp_path / "out" / "report.html").read_text()
    # A query x map similarity in memory, and online: latency and wait per frame.
    s = seqtopo.similarity(query, map_d).similarity
    online = seqtopo.localize_sequences(s, online=True, ground_truth="same-index")
    assert online.online and len(online.latencies) == 40 and len(online.waits) == 40
    assert "latency median" in repr(online)
    # With a lag (fixed-lag smoothing) every frame is answered once, the last ones at the end of the query.
    lagged = seqtopo.localize_sequences(s, online=True, lag=5, ground_truth="same-index")
    assert lagged.queries == 40 and len(lagged.map) == 40 and len(lagged.latencies) == 40
    assert seqtopo.LocalizeConfig(lag=5).lag == 5 and seqtopo.LocalizeConfig().lag == 0
    with pytest.raises(TypeError, match="MapRun"):
        seqtopo.write_report(object(), tmp_path / "x")


def test_localize_finds_a_query_driven_twice_as_fast_at_its_speed():
    # Query frame q was taken at map frame 2q + 10: found at the default speeds, lost at the recorded speed alone.
    rng = np.random.default_rng(8)
    s = rng.uniform(0.0, 0.6, (40, 100)).astype(np.float32)
    for q in range(40):
        s[q, 2 * q + 10] = 0.75
    truth = 2 * np.arange(40) + 10
    assert seqtopo.LocalizeConfig().speeds[0] == 1.0 and len(seqtopo.LocalizeConfig().speeds) > 1
    found = seqtopo.localize(s)
    alone = seqtopo.localize(s, seqtopo.LocalizeConfig(speeds=[1.0]))
    assert np.mean(np.abs(found.map - truth) <= 1) >= 0.9
    assert np.mean(np.abs(alone.map - truth) <= 1) < 0.5
    with pytest.raises(ValueError, match="speeds"):
        seqtopo.LocalizeConfig(speeds=[2.0, 1.0])


def test_the_console_entry_point_runs_the_tool():
    from seqtopo import _cli

    cli = os.environ.get("SEQTOPO_CLI")
    if not cli:
        pytest.skip("SEQTOPO_CLI not set")
    assert os.path.samefile(_cli._tool(), cli)
