"""The Python functions give exactly what the command line writes for the same input."""

import csv
import json

import numpy as np
import pytest

import seqtopo
from conftest import SOURCE_DIR, localization_pair, route_descriptors, run_cli


def read_loop_closures(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    pairs = np.array([[int(r["i"]), int(r["j"])] for r in rows], dtype=np.int64).reshape(-1, 2)
    scores = np.array([float(r["score"]) for r in rows], dtype=np.float32)
    return pairs, scores


def assert_alignments_equal(python, from_json):
    assert len(python) == len(from_json)
    for a, j in zip(python, from_json):
        # JSON holds the float32 score widened to double: narrowing it back is exact.
        assert np.float32(j["score"]) == np.float32(a.score)
        assert (a.direction, a.a_begin, a.a_end, a.b_begin, a.b_end) == (
            j["direction"], j["a_begin"], j["a_end"], j["b_begin"], j["b_end"])
        assert np.array_equal(a.pairs, np.array(j["pairs"], dtype=np.int64).reshape(-1, 2))


def assert_map_equal(result, out_dir):
    with open(out_dir / "map.json") as f:
        written = json.load(f)
    mine = result.to_json()
    for key in ("images", "labels", "places", "edges", "junctions", "segments"):
        assert mine[key] == written[key], key
    assert_alignments_equal(result.alignments, written["alignments"])
    assert [a["kept"] for a in written["alignments"]] == result.kept.tolist()
    pairs, scores = read_loop_closures(out_dir / "loop_closures.csv")
    assert np.array_equal(result.loop_closures, pairs)
    assert np.array_equal(result.loop_closure_scores, scores)
    confidences = np.array([float(r["confidence"]) for r in csv.DictReader(open(out_dir / "loop_closures.csv"))])
    assert np.allclose(result.loop_closure_confidences, confidences, rtol=1e-5, atol=1e-9)
    assert ((0 <= result.loop_closure_confidences) & (result.loop_closure_confidences <= 1)).all()
    assert np.array_equal(np.load(out_dir / "scores.npy"), result.scores)


@pytest.mark.parametrize("metric,kappa", [(None, None), ("l1", None), ("cosine", 2.5), ("chi2", None)])
def test_similarity_equals_cli(cli, tmp_path, metric, kappa):
    d = route_descriptors()
    np.save(tmp_path / "descriptors.npy", d)
    args = ["similarity", tmp_path / "descriptors.npy", "--out", tmp_path / "out"]
    if metric:
        args += ["--metric", metric]
    if kappa:
        args += ["--kappa", kappa]
    run_cli(cli, *args)
    expected = np.load(tmp_path / "out" / "similarity.npy")
    result = seqtopo.similarity(d, metric=metric, kappa=kappa)
    assert result.similarity.dtype == np.float32
    assert np.array_equal(result.similarity, expected)
    assert result.metric == (metric or "cosine")
    assert result.kappa_auto == (kappa is None)
    # The same through the path form, and from float64 input (converted to float32 as the .npy reader does).
    assert np.array_equal(seqtopo.similarity(tmp_path / "descriptors.npy", metric=metric, kappa=kappa).similarity, expected)
    assert np.array_equal(seqtopo.similarity(d.astype(np.float64), metric=metric, kappa=kappa).similarity, expected)


def test_similarity_against_equals_cli(cli, tmp_path):
    map_d, query = localization_pair()
    np.save(tmp_path / "query.npy", query)
    np.save(tmp_path / "map.npy", map_d)
    run_cli(cli, "similarity", tmp_path / "query.npy", "--against", tmp_path / "map.npy", "--out", tmp_path / "out")
    result = seqtopo.similarity(query, map_d)
    assert result.similarity.shape == (40, 80)
    assert np.array_equal(result.similarity, np.load(tmp_path / "out" / "similarity.npy"))


def test_build_map_equals_cli_on_similarity_npy(cli, tmp_path):
    s = seqtopo.similarity(route_descriptors()).similarity
    np.save(tmp_path / "route_similarity.npy", s)
    run_cli(cli, "map", tmp_path / "route_similarity.npy", "--out", tmp_path / "out")
    result = seqtopo.build_map(s)
    # The walk revisits places forward and backwards: both kinds of loop closure must be there.
    assert {a.direction for a, kept in zip(result.alignments, result.kept) if kept} == {"forward", "reverse"}
    assert len(result.places) < result.images
    assert_map_equal(result, tmp_path / "out")
    # A path goes through the same pipeline as the command.
    assert_map_equal(seqtopo.build_map(tmp_path / "route_similarity.npy"), tmp_path / "out")


def test_build_map_with_options_equals_cli(cli, tmp_path):
    s = seqtopo.similarity(route_descriptors(seed=3)).similarity
    np.save(tmp_path / "route_similarity.npy", s)
    run_cli(cli, "map", tmp_path / "route_similarity.npy", "--out", tmp_path / "out", "--gap", 1, "--cap", "none",
            "--threshold", 5, "--min-separation", 6, "--contrast-window", 8, "--contrast-offset", 0.25, "--no-reverse")
    # An explicit cap on the command line replaces the one from the statistics.
    result = seqtopo.build_map(s, gap=1.0, cap=None, cap_from_statistics=False, threshold=5.0, min_separation=6,
                               contrast_window=8, contrast_offset=0.25, reverse=False)
    assert result.alignments and all(a.direction == "forward" for a in result.alignments)
    assert_map_equal(result, tmp_path / "out")


def test_build_map_from_descriptors_npy_equals_cli(cli, tmp_path):
    np.save(tmp_path / "descriptors.npy", route_descriptors(seed=5))
    run_cli(cli, "map", tmp_path / "descriptors.npy", "--out", tmp_path / "out")
    result = seqtopo.build_map_from_images(tmp_path / "descriptors.npy")
    assert len(result.similarities) == 1
    assert_map_equal(result, tmp_path / "out")
    assert np.array_equal(result.similarities[0].similarity, np.load(tmp_path / "out" / "similarity.npy"))


def test_build_map_from_image_folder_equals_cli(cli, tmp_path):
    """The bundled corridor walk (84 images): two descriptors fused, as `seqtopo map` does by default."""
    folder = SOURCE_DIR / "data" / "rtabmap-corridor"
    run_cli(cli, "map", folder, "--out", tmp_path / "out")
    result = seqtopo.build_map_from_images(folder)
    assert [r.metric for r in result.similarities] == ["chi2", "sad"]
    assert result.images == 84 and result.kept.any()
    assert_map_equal(result, tmp_path / "out")


def test_localize_equals_cli(cli, tmp_path):
    map_d, query = localization_pair()
    s = seqtopo.similarity(query, map_d).similarity
    np.save(tmp_path / "qm_similarity.npy", s)
    run_cli(cli, "localize", "--map", tmp_path / "qm_similarity.npy", "--out", tmp_path / "out")
    result = seqtopo.localize(s)
    with open(tmp_path / "out" / "matches.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == len(result.map) == 40
    for q, row in enumerate(rows):
        assert int(row["query"]) == q
        assert int(row["map"]) == result.map[q]  # every frame has its best guess
        assert row["score"] == format(float(result.score[q]), ".6g")
        assert row["confidence"] == format(float(result.confidence[q]), ".6g")
        assert row["in_map"] == ("1" if result.covered[q] else "0")
    assert np.array_equal(result.covered, result.confidence >= seqtopo.LocalizeConfig().min_confidence)
    # The query drove through map frames 20..49, then somewhere new: in the map, confidently, then not.
    assert np.all(np.abs(result.map[2:28] - np.arange(22, 48)) <= 1)
    assert np.all(result.covered[2:28]) and not np.any(result.covered[34:])
    assert np.all(result.confidence[2:28] > result.confidence[34:].max())
    assert result.candidates.shape == (40, seqtopo.LocalizeConfig().candidates)
    assert np.all(result.candidates[:, 0] == result.map)


def test_localize_with_options_equals_cli(cli, tmp_path):
    map_d, query = localization_pair(seed=4)
    s = seqtopo.similarity(query, map_d[::-1].copy()).similarity  # the map driven the other way
    np.save(tmp_path / "qm_similarity.npy", s)
    run_cli(cli, "localize", "--map", tmp_path / "qm_similarity.npy", "--out", tmp_path / "out", "--gap", 1.5,
            "--threshold", 6, "--contrast-offset", 0.5, "--contrast-window", 6, "--score-window", 4, "--cap", 30)
    result = seqtopo.localize(s, seqtopo.LocalizeConfig(gap=1.5, threshold=6.0, contrast_offset=0.5, contrast_window=6,
                                                         score_window=4, cap=30.0, threads=2))
    assert "reverse" in set(result.direction[result.covered])
    with open(tmp_path / "out" / "matches.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    for q, row in enumerate(rows):
        assert row["map"] == str(result.map[q])
        assert row["score"] == format(float(result.score[q]), ".6g")
        assert row["confidence"] == format(float(result.confidence[q]), ".6g")


@pytest.mark.parametrize("options", [
    {"gap": 1.0, "reverse": True},
    {"gap": 0.5, "cap": 6.0, "threshold": 2.0, "reverse": True},
    {"gap_a": 0.5, "gap_b": 2.0, "reverse": False, "max_alignments": 3},
    {"self": True, "min_separation": 5, "reverse": True, "gap": 1.0, "threshold": 1.0},
])
def test_align_equals_cli(cli, tmp_path, options):
    s = seqtopo.similarity(route_descriptors(seed=9)).similarity
    np.save(tmp_path / "scores.npy", s)
    args = ["align", "--scores", tmp_path / "scores.npy", "--json", tmp_path / "alignments.json",
            "--max-alignments", options.get("max_alignments", 0)]
    flags = {"gap": "--gap", "gap_a": "--gap-a", "gap_b": "--gap-b", "cap": "--cap", "threshold": "--threshold",
             "min_separation": "--min-separation"}
    for key, flag in flags.items():
        if key in options:
            args += [flag, options[key]]
    if options.get("reverse"):
        args.append("--reverse")
    if options.get("self"):
        args.append("--self")
    run_cli(cli, *args)
    with open(tmp_path / "alignments.json") as f:
        written = json.load(f)["alignments"]
    result = seqtopo.align(s, **options)
    assert result
    assert_alignments_equal(result, written)


def read_matches_tsv(path):
    rows = []
    with open(path) as f:
        for line in f:
            if line.startswith("#") or line.startswith("query_id"):
                continue
            rows.append(line.rstrip("\n").split("\t"))
    return rows


@pytest.mark.parametrize("algorithm,extra", [("A", {}), ("A", {"preset": "A2-rooms", "k": 4}), ("B", {"k": 2}),
                                              ("C", {}), ("A", {"cyclic": True}), ("C", {"window": 3})])
def test_match_strings_equals_cli(cli, tmp_path, algorithm, extra):
    rng = np.random.default_rng(1)
    alphabet = list("vABCDEFGHIJKLMNOP")
    db = ["".join(rng.choice(alphabet, size=rng.integers(6, 14))) for _ in range(25)]
    queries = []
    for k in range(12):
        s = list(db[(2 * k) % 25])
        for _ in range(2):  # two random edits
            pos = int(rng.integers(0, len(s)))
            s[pos] = str(rng.choice(alphabet))
        queries.append("".join(s))
    (tmp_path / "db.tsv").write_text("".join(f"m{k}\t{s}\n" for k, s in enumerate(db)))
    (tmp_path / "q.tsv").write_text("".join(f"t{k}\t{s}\n" for k, s in enumerate(queries)))
    args = ["match-strings", "--db", tmp_path / "db.tsv", "--queries", tmp_path / "q.tsv", "--algorithm", algorithm,
            "--out", tmp_path / "out"]
    if "preset" in extra:
        args += ["--preset", extra["preset"]]
    if "k" in extra:
        args += ["--k", extra["k"]]
    if extra.get("cyclic"):
        args.append("--cyclic")
    if "window" in extra:
        args += ["--window", extra["window"]]
    run_cli(cli, *args)
    expected = read_matches_tsv(tmp_path / "out" / "matches.tsv")
    config = seqtopo.MatchConfig(algorithm=algorithm, k=extra.get("k"), cyclic=extra.get("cyclic", False))
    result = seqtopo.match_strings(db, queries, config, window=extra.get("window", 1), preset=extra.get("preset"))
    mine = []
    for q, m in enumerate(result):
        for d, score, rank, rotation in zip(m.db_index, m.score, m.rank, m.rotation):
            row = [f"t{q}", str(rank), f"m{d}", format(float(score), ".6g")]
            if extra.get("cyclic"):
                row.append(str(rotation))
            mine.append(row)
    assert mine == expected
    assert len(mine) > 0


def test_map_sequence_and_write_report_equal_cli(cli, tmp_path):
    # The bundled corridor with its ground truth, through the same library pipeline as `seqtopo map`.
    corridor = SOURCE_DIR / "data" / "rtabmap-corridor"
    run_cli(cli, "map", corridor, "--ground-truth", corridor / "ground_truth.bmp", "--out", tmp_path / "cli")
    run = seqtopo.map_sequence(corridor, ground_truth=corridor / "ground_truth.bmp")
    with open(tmp_path / "cli" / "metrics.json") as f:
        metrics = json.load(f)
    for key in ("tp", "fp", "fn", "precision", "recall", "f1", "auc", "recall_at_100_precision"):
        assert run.metrics[key] == metrics["loop_closure"][key], key
        assert run.baseline[key] == metrics["baseline"][key], key
    assert run.baseline["method"] == metrics["baseline"]["method"]
    assert_map_equal(run.map, tmp_path / "cli")
    seqtopo.write_report(run, tmp_path / "py")
    for name in ("map.json", "alignments.json", "loop_closures.csv", "metrics.json", "scores.npy", "similarity.npy"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    assert (tmp_path / "py" / "report.html").stat().st_size > 0


def test_a_ground_truth_of_every_frame_is_thinned_as_every_thins_the_frames(cli, tmp_path):
    # --every 2 with the corridor's own 84 x 84 ground truth scores as the 42 x 42 one thinned here with numpy.
    from PIL import Image

    corridor = SOURCE_DIR / "data" / "rtabmap-corridor"
    truth = np.array(Image.open(corridor / "ground_truth.bmp"))
    truth = truth[..., 0] if truth.ndim == 3 else truth
    Image.fromarray(truth[::2, ::2]).save(tmp_path / "kept.png")
    whole = seqtopo.map_sequence(corridor, every=2, ground_truth=corridor / "ground_truth.bmp")
    kept = seqtopo.map_sequence(corridor, every=2, ground_truth=tmp_path / "kept.png")
    assert whole.metrics["tp"] > 0
    for key in ("tp", "fp", "fn", "f1", "auc"):
        assert whole.metrics[key] == kept.metrics[key], key
    run_cli(cli, "map", corridor, "--every", "2", "--ground-truth", corridor / "ground_truth.bmp", "--out",
            tmp_path / "cli")
    with open(tmp_path / "cli" / "metrics.json") as f:
        assert json.load(f)["loop_closure"]["f1"] == whole.metrics["f1"]
    # A ground truth of neither the 42 frames kept nor the 83 or 84 they were kept from is refused.
    Image.fromarray(truth[:80, :80]).save(tmp_path / "short.png")
    with pytest.raises(seqtopo.InputError, match="83 to 84 frames"):
        seqtopo.map_sequence(corridor, every=2, ground_truth=tmp_path / "short.png")


def test_every_thins_descriptors_in_memory_as_the_command_thins_their_file(tmp_path):
    # A random walk whose frames 300-419 repeat 60-179 with noise; positions give the ground truth.
    rng = np.random.default_rng(11)
    x = np.cumsum(rng.standard_normal((520, 32)), axis=0).astype(np.float32)
    x[300:420] = x[60:180] + 0.3 * rng.standard_normal((120, 32)).astype(np.float32)
    positions = np.stack([np.arange(520.0), np.zeros(520)], axis=1)
    positions[300:420, 0] = np.arange(60.0, 180.0)
    positions[420:, 0] += 1000
    np.save(tmp_path / "x.npy", x)
    with open(tmp_path / "poses.csv", "w") as f:
        f.write("index,x,y\n" + "".join(f"{i},{px},{py}\n" for i, (px, py) in enumerate(positions)))
    memory = seqtopo.map_sequence(x, every=3, ground_truth=positions, gt_radius=1.5)
    sliced = seqtopo.map_sequence(x[::3], ground_truth=positions[::3], gt_radius=1.5)
    kept_truth = seqtopo.map_sequence(x, every=3, ground_truth=positions[::3], gt_radius=1.5)
    from_file = seqtopo.map_sequence(tmp_path / "x.npy", every=3, ground_truth=tmp_path / "poses.csv", gt_radius=1.5)
    assert memory.map.images == 174 and memory.metrics["tp"] > 30
    for other in (sliced, kept_truth, from_file):
        assert np.array_equal(other.map.loop_closures, memory.map.loop_closures)
        for key in ("tp", "fp", "fn", "f1"):
            assert other.metrics[key] == memory.metrics[key], key
    # A truth of neither the 174 rows kept nor the 520 recorded, and an odometry of the rows kept, are refused.
    with pytest.raises(ValueError, match="ground_truth: has 500 rows.*174 images kept, or the 520 frames"):
        seqtopo.map_sequence(x, every=3, ground_truth=positions[:500], gt_radius=1.5)
    with pytest.raises(ValueError, match="odometry: has 174 rows.*the 520 frames of the recording"):
        seqtopo.map_sequence(x, every=3, odometry=np.zeros((174, 3)))


@pytest.mark.parametrize("options, named", [
    ({"every": 2}, "every: a similarity matrix is not thinned"),
    ({"every": 0}, "every: must be an integer >= 1"),
    ({"streaming": True}, "streaming: applies to a path input"),
    ({"sparse": True}, "sparse: applies to a path input"),
    ({"descriptors": ["patch"]}, "descriptors: applies to a path input"),
    ({"input_kind": "video"}, "input_kind: applies to a path input"),
    ({"metric": "cosine"}, "metric: compares descriptors"),
])
def test_options_that_do_not_apply_to_a_matrix_in_memory_are_refused(options, named):
    # Each was silently ignored before, so the map was not the one asked for.
    matrix = np.eye(60, dtype=np.float32)
    with pytest.raises(ValueError, match=named):
        seqtopo.map_sequence(matrix, **options)


def test_paper_preset_from_python_equals_cli(cli, tmp_path):
    corridor = SOURCE_DIR / "data" / "rtabmap-corridor"
    run_cli(cli, "map", corridor, "--preset", "paper", "--out", tmp_path / "cli")
    preset = seqtopo.map_preset("paper")
    assert preset["descriptors"] == ["joint-histogram"] and preset["metric"] == "chi2"
    result = seqtopo.build_map_from_images(corridor, preset="paper")
    assert_map_equal(result, tmp_path / "cli")


def write_walk(path, n, seed=11):
    """A walk through descriptor space revisited forward and backward (a fifth of it each way)."""
    rng = np.random.default_rng(seed)
    x = np.zeros((n, 8), np.float32)
    x[0] = rng.standard_normal(8)
    for i in range(1, n):
        base = x[i - 1]
        if n // 2 <= i < n // 2 + n // 5:
            base = x[i - n // 2]
        elif n // 2 + n // 5 <= i < n // 2 + 2 * (n // 5):
            base = x[n - i]
        x[i] = base + 0.4 * rng.standard_normal(8)
    np.save(path, x)


@pytest.mark.parametrize("args, options", [
    (["--sparse", "--neighbours", "40"], {"sparse": True, "neighbours": 40}),
    (["--streaming"], {"streaming": True}),
    (["--engine", "streaming"], {"engine": "streaming"}),
    (["--engine", "fast"], {"engine": "fast"}),
])
def test_engines_of_map_sequence_equal_cli(cli, tmp_path, args, options):
    # One request from both front ends: the same engine, the same files.
    write_walk(tmp_path / "walk.npy", 600)
    run_cli(cli, "map", tmp_path / "walk.npy", *args, "--out", tmp_path / "cli")
    run = seqtopo.map_sequence(tmp_path / "walk.npy", **options)
    assert run.engine == (args[-1] if args[0] == "--engine" else args[0][2:])
    seqtopo.write_report(run, tmp_path / "py")
    for name in ("map.json", "alignments.json", "loop_closures.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    assert len((tmp_path / "cli" / "loop_closures.csv").read_text().splitlines()) > 100


def test_automatic_engine_of_map_sequence_equals_cli(cli, tmp_path, monkeypatch):
    # No engine given and a small machine: both front ends choose by the memory the run needs, here not the exact
    # engine, and write the same map. (6,000 frames, so that the tables, not the processes, decide at 1 GB.)
    write_walk(tmp_path / "walk.npy", 6000)
    monkeypatch.setenv("SEQTOPO_MEMORY_LIMIT", "1G")
    err = run_cli(cli, "map", tmp_path / "walk.npy", "--out", tmp_path / "cli").stderr
    assert "engine streaming: " in err, err
    run = seqtopo.map_sequence(tmp_path / "walk.npy")
    monkeypatch.delenv("SEQTOPO_MEMORY_LIMIT")
    assert run.engine == "streaming"
    seqtopo.write_report(run, tmp_path / "py")
    for name in ("map.json", "alignments.json", "loop_closures.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name


def corridor_laps(folder):
    """The bundled corridor's two laps (images 1-40 and 41-84) as two folders of links."""
    corridor = SOURCE_DIR / "data" / "rtabmap-corridor"
    laps = [folder / "lap1", folder / "lap2"]
    for lap, frames in zip(laps, (range(1, 41), range(41, 85))):
        lap.mkdir()
        for k in frames:
            (lap / f"{k:03d}.jpg").symlink_to(corridor / f"{k}.jpg")
    return laps


def test_map_sequence_of_sessions_equals_cli(cli, tmp_path):
    # The corridor's two laps given as two sessions, from Python as a list and from `seqtopo map A B`: one map, and no
    # edge from the first lap's last image to the second's first.
    laps = corridor_laps(tmp_path)
    run_cli(cli, "map", *laps, "--out", tmp_path / "cli")
    run = seqtopo.map_sequence(laps)
    seqtopo.write_report(run, tmp_path / "py")
    for name in ("map.json", "alignments.json", "loop_closures.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    written = json.loads((tmp_path / "cli" / "map.json").read_text())
    assert [(x["begin"], x["end"]) for x in written["sessions"]] == [(0, 40), (40, 84)]
    assert run.sessions == written["sessions"]
    with pytest.raises(ValueError, match="path: no input"):
        seqtopo.map_sequence([])


def test_a_break_inside_one_folder_is_a_session_from_python_as_from_the_cli(cli, tmp_path):
    # The corridor's frames 1-60 then 20-84, their names jumping from 60 to 1000 (a gap in their times): a session
    # break before image 60 for both front ends, and the same files.
    folder = tmp_path / "cut"
    folder.mkdir()
    corridor = SOURCE_DIR / "data" / "rtabmap-corridor"
    for k, frame in enumerate(list(range(1, 61)) + list(range(20, 85))):
        name = k + 1 if k < 60 else 1000 + k
        (folder / f"{name}.jpg").symlink_to(corridor / f"{frame}.jpg")
    result = run_cli(cli, "map", folder, "--out", tmp_path / "cli")
    assert "before image 60 " in result.stderr and "a session break" in result.stderr, result.stderr
    run = seqtopo.map_sequence(str(folder))
    seqtopo.write_report(run, tmp_path / "py")
    for name in ("map.json", "alignments.json", "loop_closures.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    assert [(s["begin"], s["end"]) for s in run.sessions] == [(0, 60), (60, 125)]
    assert run.sessions[1]["break"]["gap"] > 100 and "break" not in run.sessions[0]


def test_localize_sequences_default_descriptors_equal_cli(cli, tmp_path):
    # Without a descriptor both front ends fuse the map's default descriptors (joint histogram and patch).
    laps = corridor_laps(tmp_path)
    run_cli(cli, "localize", "--map", laps[0], "--query", laps[1], "--out", tmp_path / "cli")
    run = seqtopo.localize_sequences(laps[0], laps[1])
    seqtopo.write_report(run, tmp_path / "py")
    assert (tmp_path / "py" / "matches.csv").read_bytes() == (tmp_path / "cli" / "matches.csv").read_bytes()
    patch = seqtopo.localize_sequences(laps[0], laps[1], descriptor="patch")
    assert not np.array_equal(patch.map, run.map)  # the fusion is not the patch thumbnail alone
    # With a pairs file both score its frames as listed (no tolerance given), with the same answers as without it.
    truth = tmp_path / "truth.csv"
    truth.write_text("query,map\n" + "".join(f"{q},{q}\n" for q in range(40)))
    run_cli(cli, "localize", "--map", laps[0], "--query", laps[1], "--gt", truth, "--out", tmp_path / "cli-gt")
    scored = seqtopo.localize_sequences(laps[0], laps[1], ground_truth=truth)
    seqtopo.write_report(scored, tmp_path / "py-gt")
    assert (tmp_path / "py-gt" / "matches.csv").read_bytes() == (tmp_path / "cli" / "matches.csv").read_bytes()
    cli_metrics = json.loads((tmp_path / "cli-gt" / "metrics.json").read_text())
    assert scored.tolerance == cli_metrics["tolerance"] == 0
    assert scored.metrics["recall_at_1"] == cli_metrics["recall_at_1"]
