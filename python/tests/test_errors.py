"""Errors: ValueError / seqtopo.InputError with the messages the command line prints."""

import numpy as np
import pytest

import seqtopo
from conftest import cli_error, localization_pair, route_descriptors


def test_unknown_metric_message_equals_cli(cli, tmp_path):
    np.save(tmp_path / "descriptors.npy", route_descriptors())
    expected = cli_error(cli, "similarity", tmp_path / "descriptors.npy", "--metric", "hamming", "--out", tmp_path / "o")
    with pytest.raises(ValueError) as error:
        seqtopo.similarity(route_descriptors(), metric="hamming")
    assert expected == "--metric: " + str(error.value)


def test_chi2_on_negative_values_message_equals_cli(cli, tmp_path):
    d = route_descriptors() - 0.5
    np.save(tmp_path / "descriptors.npy", d)
    expected = cli_error(cli, "similarity", tmp_path / "descriptors.npy", "--metric", "chi2", "--out", tmp_path / "o")
    with pytest.raises(ValueError) as error:
        seqtopo.similarity(d, metric="chi2")
    assert expected == f"{tmp_path / 'descriptors.npy'}: {error.value}"


def test_bad_file_is_an_input_error_with_the_cli_text(cli, tmp_path):
    d = route_descriptors()
    d[3, 5] = np.nan
    np.save(tmp_path / "descriptors.npy", d)
    expected = cli_error(cli, "map", tmp_path / "descriptors.npy", "--out", tmp_path / "o")
    with pytest.raises(seqtopo.InputError) as error:
        seqtopo.build_map_from_images(tmp_path / "descriptors.npy")
    assert str(error.value) == expected
    assert error.value.subject == str(tmp_path / "descriptors.npy")
    assert error.value.message == "non-finite value at row 3, column 5"
    assert isinstance(error.value, ValueError)
    # The same values given as an array name the argument instead of the file.
    with pytest.raises(ValueError, match="^descriptors: non-finite value at row 3, column 5$"):
        seqtopo.similarity(d)


def test_missing_folder_is_an_input_error():
    with pytest.raises(seqtopo.InputError) as error:
        seqtopo.build_map_from_images("/nonexistent/folder")
    assert error.value.subject == "/nonexistent/folder"


def test_non_finite_scores_message_equals_cli(cli, tmp_path):
    s = np.zeros((4, 5), dtype=np.float32)
    s[0, 1] = np.inf
    np.save(tmp_path / "scores.npy", s)
    expected = cli_error(cli, "align", "--scores", tmp_path / "scores.npy")
    with pytest.raises(ValueError) as error:
        seqtopo.align(s)
    assert str(error.value) == "scores: non-finite value at row 0, column 1"
    assert expected.split(": ", 1)[1] == str(error.value).split(": ", 1)[1]


def test_localize_setting_message_equals_cli(cli, tmp_path):
    map_d, query = localization_pair()
    s = seqtopo.similarity(query, map_d).similarity
    np.save(tmp_path / "qm_similarity.npy", s)
    expected = cli_error(cli, "localize", "--map", tmp_path / "qm_similarity.npy", "--gap", -1, "--out", tmp_path / "o")
    with pytest.raises(ValueError) as error:
        seqtopo.localize(s, gap=-1.0)
    # The command line refuses the text while parsing, the library the value: both state the same limit.
    assert expected == "--gap: expected a finite number >= 0, got '-1' (see seqtopo localize --help)"
    assert str(error.value) == "gap must be a finite number >= 0"


@pytest.mark.parametrize("option, value", [("--algorithm", "D"), ("--preset", "A9")])
def test_unknown_match_strings_setting_message_equals_cli(cli, tmp_path, option, value):
    (tmp_path / "db.tsv").write_text("m0\tvAB\n")
    expected = cli_error(cli, "match-strings", "--db", tmp_path / "db.tsv", "--queries", tmp_path / "db.tsv",
                         option, value, "--out", tmp_path / "o")
    with pytest.raises(ValueError) as error:
        seqtopo.match_strings(["vAB"], ["vAB"], **{option[2:]: value})
    assert expected == option + ": " + str(error.value)


def test_misuse_raises_value_error():
    with pytest.raises(ValueError, match="square"):
        seqtopo.build_map(np.zeros((3, 4), dtype=np.float32))
    with pytest.raises(ValueError, match="2-D"):
        seqtopo.align(np.zeros(5, dtype=np.float32))
    with pytest.raises(ValueError, match="kappa must be positive"):
        seqtopo.similarity(route_descriptors(), kappa=-1.0)
    with pytest.raises(ValueError, match="empty"):
        seqtopo.localize(np.zeros((0, 3), dtype=np.float32))
    with pytest.raises(ValueError):
        seqtopo.align(np.ones((4, 4), dtype=np.float32), gap=-1.0)
    with pytest.raises(ValueError, match="descriptors differ in length|dimension"):
        seqtopo.similarity(np.ones((3, 4), np.float32), np.ones((3, 5), np.float32))


def test_truth_and_odometry_of_another_length_or_not_finite_are_refused():
    d = route_descriptors()
    n = len(d)
    xy = np.stack([np.arange(n, dtype=np.float32), np.zeros(n, np.float32)], axis=1)
    odometry = np.zeros((n, 3), np.float32)
    # Each of these was once mapped and scored against the wrong images (F1 0 or a wrong F1, no error).
    bad = [
        (dict(ground_truth=np.eye(5)), "ground_truth: 5 rows for 116 images"),
        (dict(ground_truth=xy[:10], gt_radius=2.0), "ground_truth: 10 rows for 116 images"),
        (dict(ground_truth=np.where(np.eye(n) > 0, np.nan, 0)), "ground_truth: non-finite"),
        (dict(odometry=odometry[:-1]), "odometry: 115 rows for 116 images"),
        (dict(odometry=np.where(np.arange(n)[:, None] == 7, np.nan, odometry)), "odometry: non-finite value at row 7"),
        (dict(gt_places=list(range(3))), "gt_places: 3 places for 116 images"),
        (dict(gt_poses=np.zeros((4, 3))), "gt_poses: 4 rows for 116 images"),
    ]
    for kwargs, message in bad:
        with pytest.raises(ValueError, match=message):
            seqtopo.map_sequence(d, **kwargs)
    seqtopo.map_sequence(d, ground_truth=xy, gt_radius=2.0, odometry=odometry)  # the right lengths map


@pytest.mark.parametrize("field, value, message", [
    ("frames_per_place", -3.0, "frames_per_place must be >= 1"),
    ("frames_per_place", 0.0, "frames_per_place must be >= 1"),
    ("max_e_value", 0.0, "significance.max_e_value must be > 0"),
    ("threshold", -1.0, "significance.threshold must be >= 0"),
    ("gap", float("nan"), "search.gap must be >= 0"),
])
def test_a_map_config_out_of_range_names_its_field(field, value, message):
    config = seqtopo.MapConfig()
    setattr(config, field, value)
    with pytest.raises(ValueError, match="MapConfig." + message):
        seqtopo.build_map(seqtopo.similarity(route_descriptors()).similarity, config)


def test_localize_errors_name_the_array_arguments_not_their_scratch_files():
    s = seqtopo.similarity(route_descriptors()[:40], route_descriptors()[40:]).similarity
    with pytest.raises((ValueError, seqtopo.InputError)) as error:
        seqtopo.localize_sequences(s, ground_truth=[(0, 5000)])
    assert str(error.value).startswith("ground_truth"), str(error.value)
    assert "truth.csv" not in str(error.value)


@pytest.mark.parametrize("override, message", [
    ({"contrast_window": -3}, "contrast_window: must be an integer >= 0, got -3"),
    ({"min_separation": 2.5}, "min_separation: must be an integer >= 0, got 2.5"),
    ({"gap": "x"}, "gap: must be a number, got 'x'"),
    ({"reverse": "no"}, "reverse: must be True or False, got 'no'"),
])
def test_a_config_override_of_the_wrong_kind_names_itself(override, message):
    # pybind11 alone answers with every constructor argument and not the one it could not take.
    with pytest.raises(ValueError) as error:
        seqtopo.map_sequence(np.eye(40, dtype=np.float32), **override)
    assert str(error.value) == message
    with pytest.raises(ValueError) as error:
        seqtopo.build_map(np.eye(40, dtype=np.float32), **override)
    assert str(error.value) == message


@pytest.mark.parametrize("call", [
    lambda: seqtopo.similarity(np.eye(4, dtype=np.float32), threads=-1),
    lambda: seqtopo.similarity(np.eye(4, dtype=np.float32), threads=2.5),
    lambda: seqtopo.align(np.eye(4, dtype=np.float32), threads=-1),
    lambda: seqtopo.map_sequence(np.eye(40, dtype=np.float32), threads="2"),
    lambda: seqtopo.localize_sequences(np.eye(8, dtype=np.float32), tolerance=-1),
    lambda: seqtopo.localize_sequences(np.eye(8, dtype=np.float32), every=0),
    lambda: seqtopo.match_strings(["vAv"], ["vAv"], window=-2),
])
def test_a_count_argument_out_of_range_is_a_value_error_naming_it(call):
    # The errors section documents ValueError; pybind11 alone raises TypeError ("incompatible function arguments").
    with pytest.raises(ValueError, match=r"^(threads|tolerance|every|window): must be an integer >= [01], got "):
        call()
