"""The config classes have the C++ structs' fields and defaults, and keyword arguments override them."""

import inspect
import re

import pytest

import seqtopo
from conftest import SOURCE_DIR, run_cli

NUMBER = r"(-?[0-9][0-9'.eE+-]*)[FfUu]?"


def header_defaults(header: str, struct: str) -> dict:
    """`name = number;` members of a struct in a C++ header: the defaults as the library states them."""
    text = (SOURCE_DIR / "include" / "seqtopo" / header).read_text()
    body = re.search(r"struct " + struct + r" \{(.*?)\n\};", text, re.S).group(1)
    values = {}
    for name, value in re.findall(r"\b(\w+) = " + NUMBER + r";", body):
        values[name] = float(value.replace("'", ""))
    for name, value in re.findall(r"\b(\w+) = (true|false);", body):
        values[name] = value == "true"
    return values


@pytest.mark.parametrize("cls,header,struct", [
    (seqtopo.MapConfig, "mapping/map_builder.hpp", "MapConfig"),
    (seqtopo.LocalizeConfig, "localize/localize.hpp", "LocalizeConfig"),
    (seqtopo.AlignConfig, "align/local_alignment.hpp", "AlignConfig"),
    (seqtopo.PruningConfig, "mapping/pruning.hpp", "PruningConfig"),
    (seqtopo.TopologyConfig, "mapping/topological_map.hpp", "TopologyConfig"),
    (seqtopo.KappaRule, "similarity/similarity_from_distance.hpp", "KappaRule"),
    (seqtopo.EditCosts, "strings/costs.hpp", "EditCosts"),
    (seqtopo.MatchConfig, "strings/localization.hpp", "MatchConfig"),
])
def test_defaults_are_the_headers(cls, header, struct):
    expected = header_defaults(header, struct)
    assert expected, f"no defaults parsed from {header}"
    config = cls()
    for name, value in expected.items():
        actual = getattr(config, name)
        if isinstance(value, bool):
            assert actual is value, name
        else:
            assert actual == pytest.approx(value, rel=1e-6), name


def test_optional_defaults():
    assert seqtopo.MapConfig().cap == pytest.approx(40.0)  # std::optional<float> cap = 40.0F
    assert seqtopo.LocalizeConfig().cap is None            # std::optional<float> cap; (none)
    assert seqtopo.AlignConfig().cap is None
    assert seqtopo.AlignConfig().max_alignments is None     # SIZE_MAX: no limit
    assert seqtopo.MatchConfig().k is None                  # kNoLimit
    assert seqtopo.MatchConfig().algorithm == "A"
    assert seqtopo.PruningConfig().rank == "score_then_length"


def test_defaults_equal_the_command_line_help(cli):
    """`seqtopo map --help` prints the defaults of the C++ MapConfig."""
    text = run_cli(cli, "map", "--help").stdout
    config = seqtopo.MapConfig()
    cap = re.search(r"^\s*--cap\b[^\n]*\(default: ([0-9.]+) x [^;]*; ([0-9.]+) without --e-value", text, re.M)
    assert cap, "cap"
    assert (float(cap.group(1)), float(cap.group(2))) == pytest.approx((config.cap_factor, config.cap))
    for option, value in [("gap", config.gap), ("threshold", config.threshold),
                          ("min-separation", config.min_separation), ("contrast-window", config.contrast_window),
                          ("contrast-offset", config.contrast_offset)]:
        match = re.search(r"^\s*--" + option + r"\b[^\n]*\(default ([0-9.]+)", text, re.M)
        assert match, option
        assert float(match.group(1)) == pytest.approx(value), option


def test_keywords_override_and_nested_configs():
    c = seqtopo.MapConfig(gap=2.0, cap=None, pruning=seqtopo.PruningConfig(rank="length_then_score"))
    assert c.gap == 2.0 and c.cap is None and c.pruning.rank == "length_then_score"
    assert c.threshold == seqtopo.MapConfig().threshold
    c.pruning.min_retained_fraction = 0.75
    assert c.pruning.min_retained_fraction == 0.75
    assert "gap=2.0" in repr(c)
    with pytest.raises(TypeError):
        seqtopo.MapConfig(2.0)  # keyword-only
    with pytest.raises(TypeError):
        seqtopo.build_map([[1.0]], no_such_field=1)
    with pytest.raises(ValueError, match="unknown rank"):
        seqtopo.PruningConfig(rank="longest")


def test_function_defaults_come_from_the_configs():
    sig = inspect.signature(seqtopo.align)
    d = seqtopo.AlignConfig()
    assert sig.parameters["threshold"].default == d.threshold
    assert sig.parameters["min_separation"].default == d.min_separation
    assert sig.parameters["cap"].default == d.cap


def test_presets():
    assert "A2-rooms" in seqtopo.preset_names()
    rooms = seqtopo.preset_costs("A2-rooms")
    assert rooms.colour_difference == pytest.approx(0.75)
    a1 = seqtopo.preset_costs("A1")
    d = seqtopo.EditCosts()
    assert (a1.deletion, a1.insertion, a1.colour_difference, a1.coincidence, a1.discordance) == \
        (d.deletion, d.insertion, d.colour_difference, d.coincidence, d.discordance)


def test_alignment_set_default_is_the_headers():
    text = (SOURCE_DIR / "include" / "seqtopo" / "mapping" / "map_builder.hpp").read_text()
    default = re.search(r"alignment_set = align::AlignmentSet::(\w+);", text).group(1).replace("_", "-")
    assert seqtopo.MapConfig().alignment_set == default
    other = "locally-optimal" if default == "non-intersecting" else "non-intersecting"
    assert seqtopo.MapConfig(alignment_set=other).alignment_set == other
    with pytest.raises(ValueError, match="locally-optimal or non-intersecting"):
        seqtopo.MapConfig(alignment_set="all")
