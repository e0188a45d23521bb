// The config classes: the C++ structs themselves, so their defaults are the library's by construction.
#include <pybind11/stl.h>

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/localize/localize.hpp"
#include "seqtopo/mapping/map_builder.hpp"
#include "seqtopo/similarity/similarity_from_distance.hpp"
#include "seqtopo/strings/localization.hpp"

namespace seqtopo::python {
namespace {

// "Name(a=1, b=2)" from the object's own attributes.
std::string field_repr(const py::object& self, const char* type, const std::vector<const char*>& fields) {
  std::string text = std::string(type) + "(";
  for (std::size_t k = 0; k < fields.size(); ++k) {
    if (k > 0) text += ", ";
    text += std::string(fields[k]) + "=" + py::repr(self.attr(fields[k])).cast<std::string>();
  }
  return text + ")";
}

template <typename Class>
void add_repr(Class& c, const char* type, std::vector<const char*> fields) {
  c.def("__repr__", [type, fields](const py::object& self) { return field_repr(self, type, fields); });
}

// "no limit" is None in Python and SIZE_MAX in C++.
std::optional<std::size_t> limit_to_python(std::size_t value) {
  if (value == std::numeric_limits<std::size_t>::max()) return std::nullopt;
  return value;
}
std::size_t limit_from_python(std::optional<std::size_t> value) {
  return value.value_or(std::numeric_limits<std::size_t>::max());
}

void bind_align(py::module_& m) {
  const align::AlignConfig d{};
  py::class_<align::AlignConfig> c(
      m, "AlignConfig",
      "Settings of the local-alignment engine (C++ seqtopo::align::AlignConfig).\n\n"
      "gap_a / gap_b: penalty per element of A / B skipped by a gap; cap: upper bound on the\n"
      "cumulative score (None: classical Smith-Waterman); threshold: minimum reported score;\n"
      "max_alignments: stop after this many (None: all); self: A and B are one sequence, only\n"
      "pairs with i - j >= min_separation are searched.");
  c.def(py::init([](float gap_a, float gap_b, std::optional<float> cap, float threshold,
                    std::optional<std::size_t> max_alignments, bool self, std::size_t min_separation) {
          align::AlignConfig config;
          config.gap_a = gap_a;
          config.gap_b = gap_b;
          config.cap = cap;
          config.threshold = threshold;
          config.max_alignments = limit_from_python(max_alignments);
          config.self = self;
          config.min_separation = min_separation;
          return config;
        }),
        py::kw_only(), py::arg("gap_a") = d.gap_a, py::arg("gap_b") = d.gap_b, py::arg("cap") = d.cap,
        py::arg("threshold") = d.threshold, py::arg("max_alignments") = limit_to_python(d.max_alignments),
        py::arg("self") = d.self, py::arg("min_separation") = d.min_separation)
      .def_readwrite("gap_a", &align::AlignConfig::gap_a)
      .def_readwrite("gap_b", &align::AlignConfig::gap_b)
      .def_readwrite("cap", &align::AlignConfig::cap)
      .def_readwrite("threshold", &align::AlignConfig::threshold)
      .def_property(
          "max_alignments", [](const align::AlignConfig& a) { return limit_to_python(a.max_alignments); },
          [](align::AlignConfig& a, std::optional<std::size_t> v) { a.max_alignments = limit_from_python(v); })
      .def_readwrite("self", &align::AlignConfig::self)
      .def_readwrite("min_separation", &align::AlignConfig::min_separation);
  add_repr(c, "AlignConfig", {"gap_a", "gap_b", "cap", "threshold", "max_alignments", "self", "min_separation"});
}

void bind_map(py::module_& m) {
  using mapping::MapConfig;
  using mapping::PruningConfig;
  using mapping::TopologyConfig;

  py::class_<PruningConfig> pruning(
      m, "PruningConfig",
      "Per-column pruning (C++ seqtopo::mapping::PruningConfig). rank: 'score_then_length'\n"
      "(default) or 'length_then_score' (the paper's longest matching subsequence);\n"
      "min_retained_fraction: an alignment is kept when at least this share of its pairs survive.");
  auto rank_name = [](PruningConfig::Rank r) {
    return std::string(r == PruningConfig::Rank::score_then_length ? "score_then_length" : "length_then_score");
  };
  auto rank_value = [](const std::string& name) {
    if (name == "score_then_length") return PruningConfig::Rank::score_then_length;
    if (name == "length_then_score") return PruningConfig::Rank::length_then_score;
    throw std::invalid_argument("unknown rank '" + name + "' (expected score_then_length or length_then_score)");
  };
  const PruningConfig dp{};
  pruning
      .def(py::init([rank_value](const std::string& rank, double min_retained_fraction) {
             PruningConfig config;
             config.rank = rank_value(rank);
             config.min_retained_fraction = min_retained_fraction;
             return config;
           }),
           py::kw_only(), py::arg("rank") = rank_name(dp.rank),
           py::arg("min_retained_fraction") = dp.min_retained_fraction)
      .def_property(
          "rank", [rank_name](const PruningConfig& p) { return rank_name(p.rank); },
          [rank_value](PruningConfig& p, const std::string& name) { p.rank = rank_value(name); })
      .def_readwrite("min_retained_fraction", &PruningConfig::min_retained_fraction);
  add_repr(pruning, "PruningConfig", {"rank", "min_retained_fraction"});

  const TopologyConfig dt{};
  py::class_<TopologyConfig> topology(
      m, "TopologyConfig",
      "Topology (C++ seqtopo::mapping::TopologyConfig). u_turn_separation [frames]: a reverse\n"
      "alignment meeting itself closer than this is a U-turn, not a junction. reduce_transitive: leave out an\n"
      "edge p - q traversed less often than both edges of a route p - x - q (set by MapConfig.clean_graph).\n"
      "junction_region [edges]: branching places this close to one another are one junction (0: each is its\n"
      "own; MapConfig.clean_graph sets the shortest revisit, 3 places).");
  topology
      .def(py::init([](std::size_t u_turn_separation, bool reduce_transitive, std::size_t junction_region) {
             TopologyConfig c;
             c.u_turn_separation = u_turn_separation;
             c.reduce_transitive = reduce_transitive;
             c.junction_region = junction_region;
             return c;
           }),
           py::kw_only(), py::arg("u_turn_separation") = dt.u_turn_separation,
           py::arg("reduce_transitive") = dt.reduce_transitive, py::arg("junction_region") = dt.junction_region)
      .def_readwrite("u_turn_separation", &TopologyConfig::u_turn_separation)
      .def_readwrite("reduce_transitive", &TopologyConfig::reduce_transitive)
      .def_readwrite("junction_region", &TopologyConfig::junction_region);
  add_repr(topology, "TopologyConfig", {"u_turn_separation", "reduce_transitive", "junction_region"});

  const MapConfig d{};
  auto labelling_name = [](mapping::LabelSettings::Method l) {
    return std::string(l == mapping::LabelSettings::Method::consistent ? "consistent" : "pruned_transitive");
  };
  auto labelling_value = [](const std::string& name) {
    if (name == "consistent") return mapping::LabelSettings::Method::consistent;
    if (name == "pruned_transitive") return mapping::LabelSettings::Method::pruned_transitive;
    throw std::invalid_argument("unknown labelling '" + name + "' (expected consistent or pruned_transitive)");
  };
  py::class_<MapConfig> c(
      m, "MapConfig",
      "Settings of build_map (C++ seqtopo::mapping::MapConfig), same names and defaults.\n\n"
      "contrast_window [places] (0: align the raw S, as the paper), contrast_offset [standard\n"
      "deviations], gap (penalty per skipped image), cap (None: no cap; with cap_from_statistics the cap\n"
      "is cap_factor x the score a significant alignment needs), max_e_value (None: the fixed threshold),\n"
      "threshold (minimum alignment score of a revisit without significance), min_revisit_places,\n"
      "adapt_offset (raise the offset until chance alignments stay short), min_separation [places],\n"
      "place_units (False: windows in frames, as the paper), frames_per_place (None: estimated),\n"
      "reverse (also search paths revisited backwards), labelling ('consistent' or 'pruned_transitive'),\n"
      "max_visit_span [places], clean_graph (the place graph's clean-up, mapping/graph_cleanup.hpp), pruning "
      "(PruningConfig), topology (TopologyConfig), threads (forward and\n"
      "reverse passes in parallel when > 1; the result does not depend on it), alignment_set\n"
      "('non-intersecting' or 'locally-optimal', docs/alignment_sets.md), trim_chance_ends (alignments' ends\n"
      "cut back where their pairs are more likely chance than revisit, significance/alignment_ends.hpp),\n"
      "odometry_evidence (with odometry: an alignment's agreement with it lowers its E-value, map_builder.hpp),\n"
      "drop_blind_descriptors (a fused descriptor that sees no revisit is left out, up to max_blind_check_frames),\n"
      "mask_low_information (dark or near-uniform images carry no evidence of a revisit),\n"
      "hubness_neighbours [places] (hubness correction of the similarities; 0: off), confidence_tolerance [frames]\n"
      "(a pair's confidence is the probability its partner is within it).");
  c.def(py::init([labelling_value](
                     std::size_t contrast_window, float contrast_offset, float gap, std::optional<float> cap,
                     bool cap_from_statistics, float cap_factor, std::optional<double> max_e_value, float threshold,
                     double min_revisit_places, bool adapt_offset, std::size_t min_separation, bool place_units,
                     std::optional<double> frames_per_place, bool reverse, const std::string& labelling,
                     double max_visit_span, bool clean_graph, PruningConfig pruning, TopologyConfig topology,
                     unsigned threads, float contrast_offset_step, float max_contrast_offset,
                     std::size_t fit_alignments, std::size_t confidence_band, const std::string& alignment_set,
                     bool trim_chance_ends, bool odometry_evidence, std::optional<float> max_global_rate,
                     bool drop_blind_descriptors, std::size_t max_blind_check_frames, bool mask_low_information,
                     double hubness_neighbours, std::size_t confidence_tolerance) {
          MapConfig config;
          config.score.contrast_window = contrast_window;
          config.score.contrast_offset = contrast_offset;
          config.search.gap = gap;
          config.search.cap = cap;
          config.cap_from_statistics = cap_from_statistics;
          config.cap_factor = cap_factor;
          config.significance.max_e_value = max_e_value;
          config.significance.threshold = threshold;
          config.min_revisit_places = min_revisit_places;
          config.phase.adapt_offset = adapt_offset;
          config.search.min_separation = min_separation;
          config.unit = place_units ? align::Unit::places : align::Unit::frames;
          config.frames_per_place = frames_per_place;
          config.search.reverse = reverse;
          config.labels.method = labelling_value(labelling);
          config.labels.max_visit_span = max_visit_span;
          config.graph.clean = clean_graph;
          config.labels.pruning = pruning;
          config.graph.topology = topology;
          config.threads = threads;
          config.phase.contrast_offset_step = contrast_offset_step;
          config.phase.max_contrast_offset = max_contrast_offset;
          config.fit_alignments = fit_alignments;
          config.confidence_band = confidence_band;
          config.alignment_set = align::parse_alignment_set(alignment_set);
          config.trim_chance_ends = trim_chance_ends;
          config.odometry.evidence = odometry_evidence;
          config.phase.max_global_rate = max_global_rate;
          config.drop_blind_descriptors = drop_blind_descriptors;
          config.max_blind_check_frames = max_blind_check_frames;
          config.mask_low_information = mask_low_information;
          config.hubness_neighbours = hubness_neighbours;
          config.confidence_tolerance = confidence_tolerance;
          return config;
        }),
        py::kw_only(), py::arg("contrast_window") = d.score.contrast_window,
        py::arg("contrast_offset") = d.score.contrast_offset, py::arg("gap") = d.search.gap,
        py::arg("cap") = d.search.cap, py::arg("cap_from_statistics") = d.cap_from_statistics,
        py::arg("cap_factor") = d.cap_factor, py::arg("max_e_value") = d.significance.max_e_value,
        py::arg("threshold") = d.significance.threshold, py::arg("min_revisit_places") = d.min_revisit_places,
        py::arg("adapt_offset") = d.phase.adapt_offset, py::arg("min_separation") = d.search.min_separation,
        py::arg("place_units") = d.unit == align::Unit::places, py::arg("frames_per_place") = d.frames_per_place,
        py::arg("reverse") = d.search.reverse, py::arg("labelling") = labelling_name(d.labels.method),
        py::arg("max_visit_span") = d.labels.max_visit_span, py::arg("clean_graph") = d.graph.clean,
        py::arg("pruning") = d.labels.pruning, py::arg("topology") = d.graph.topology, py::arg("threads") = d.threads,
        py::arg("contrast_offset_step") = d.phase.contrast_offset_step,
        py::arg("max_contrast_offset") = d.phase.max_contrast_offset, py::arg("fit_alignments") = d.fit_alignments,
        py::arg("confidence_band") = d.confidence_band,
        py::arg("alignment_set") = std::string(align::to_string(d.alignment_set)),
        py::arg("trim_chance_ends") = d.trim_chance_ends, py::arg("odometry_evidence") = d.odometry.evidence,
        py::arg("max_global_rate") = d.phase.max_global_rate,
        py::arg("drop_blind_descriptors") = d.drop_blind_descriptors,
        py::arg("max_blind_check_frames") = d.max_blind_check_frames,
        py::arg("mask_low_information") = d.mask_low_information, py::arg("hubness_neighbours") = d.hubness_neighbours,
        py::arg("confidence_tolerance") = d.confidence_tolerance)
      .def_property("contrast_window", section_getter(&MapConfig::score, &align::ScoreSettings::contrast_window),
                    section_setter(&MapConfig::score, &align::ScoreSettings::contrast_window))
      .def_property("contrast_offset", section_getter(&MapConfig::score, &align::ScoreSettings::contrast_offset),
                    section_setter(&MapConfig::score, &align::ScoreSettings::contrast_offset))
      .def_property("gap", section_getter(&MapConfig::search, &align::SearchSettings::gap),
                    section_setter(&MapConfig::search, &align::SearchSettings::gap))
      .def_property("cap", section_getter(&MapConfig::search, &align::SearchSettings::cap),
                    section_setter(&MapConfig::search, &align::SearchSettings::cap))
      .def_readwrite("cap_from_statistics", &MapConfig::cap_from_statistics)
      .def_readwrite("cap_factor", &MapConfig::cap_factor)
      .def_property("max_e_value", section_getter(&MapConfig::significance, &align::SignificanceSettings::max_e_value),
                    section_setter(&MapConfig::significance, &align::SignificanceSettings::max_e_value))
      .def_property("threshold", section_getter(&MapConfig::significance, &align::SignificanceSettings::threshold),
                    section_setter(&MapConfig::significance, &align::SignificanceSettings::threshold))
      .def_readwrite("min_revisit_places", &MapConfig::min_revisit_places)
      .def_property("adapt_offset", section_getter(&MapConfig::phase, &align::PhaseSettings::adapt_offset),
                    section_setter(&MapConfig::phase, &align::PhaseSettings::adapt_offset))
      .def_property("contrast_offset_step",
                    section_getter(&MapConfig::phase, &align::PhaseSettings::contrast_offset_step),
                    section_setter(&MapConfig::phase, &align::PhaseSettings::contrast_offset_step))
      .def_property("max_contrast_offset",
                    section_getter(&MapConfig::phase, &align::PhaseSettings::max_contrast_offset),
                    section_setter(&MapConfig::phase, &align::PhaseSettings::max_contrast_offset))
      .def_property("max_global_rate", section_getter(&MapConfig::phase, &align::PhaseSettings::max_global_rate),
                    section_setter(&MapConfig::phase, &align::PhaseSettings::max_global_rate))
      .def_property("min_separation", section_getter(&MapConfig::search, &align::SearchSettings::min_separation),
                    section_setter(&MapConfig::search, &align::SearchSettings::min_separation))
      .def_property(
          "place_units", [](const MapConfig& x) { return x.unit == align::Unit::places; },
          [](MapConfig& x, bool places) { x.unit = places ? align::Unit::places : align::Unit::frames; })
      .def_readwrite("frames_per_place", &MapConfig::frames_per_place)
      .def_property("reverse", section_getter(&MapConfig::search, &align::SearchSettings::reverse),
                    section_setter(&MapConfig::search, &align::SearchSettings::reverse))
      .def_property(
          "labelling", [labelling_name](const MapConfig& x) { return labelling_name(x.labels.method); },
          [labelling_value](MapConfig& x, const std::string& name) { x.labels.method = labelling_value(name); })
      .def_property("max_visit_span", section_getter(&MapConfig::labels, &mapping::LabelSettings::max_visit_span),
                    section_setter(&MapConfig::labels, &mapping::LabelSettings::max_visit_span))
      .def_property("clean_graph", section_getter(&MapConfig::graph, &mapping::GraphSettings::clean),
                    section_setter(&MapConfig::graph, &mapping::GraphSettings::clean))
      .def_property("pruning", section_getter(&MapConfig::labels, &mapping::LabelSettings::pruning),
                    section_setter(&MapConfig::labels, &mapping::LabelSettings::pruning))
      .def_property("topology", section_getter(&MapConfig::graph, &mapping::GraphSettings::topology),
                    section_setter(&MapConfig::graph, &mapping::GraphSettings::topology))
      .def_readwrite("threads", &MapConfig::threads)
      .def_readwrite("fit_alignments", &MapConfig::fit_alignments)
      .def_readwrite("confidence_band", &MapConfig::confidence_band)
      .def_readwrite("trim_chance_ends", &MapConfig::trim_chance_ends)
      .def_property("odometry_evidence", section_getter(&MapConfig::odometry, &mapping::OdometrySettings::evidence),
                    section_setter(&MapConfig::odometry, &mapping::OdometrySettings::evidence))
      .def_readwrite("drop_blind_descriptors", &MapConfig::drop_blind_descriptors)
      .def_readwrite("max_blind_check_frames", &MapConfig::max_blind_check_frames)
      .def_readwrite("mask_low_information", &MapConfig::mask_low_information)
      .def_readwrite("hubness_neighbours", &MapConfig::hubness_neighbours)
      .def_readwrite("confidence_tolerance", &MapConfig::confidence_tolerance)
      .def_property(
          "alignment_set", [](const MapConfig& x) { return std::string(align::to_string(x.alignment_set)); },
          [](MapConfig& x, const std::string& name) { x.alignment_set = align::parse_alignment_set(name); });
  add_repr(c, "MapConfig",
           {"contrast_window", "contrast_offset", "gap", "cap", "cap_from_statistics", "max_e_value", "threshold",
            "min_separation", "frames_per_place", "reverse", "labelling", "pruning", "topology", "threads",
            "alignment_set"});
}

void bind_localize(py::module_& m) {
  using localize::LocalizeConfig;
  const LocalizeConfig d{};
  py::class_<LocalizeConfig> c(
      m, "LocalizeConfig",
      "Settings of localize (C++ seqtopo::localize::LocalizeConfig), same names and defaults.\n\n"
      "contrast_window [map frames] (0: whole row), enhance, contrast_offset [standard deviations], gap,\n"
      "cap (None: none), threshold (alignments below it count as chance when there are too few for the\n"
      "significance statistics), reverse, max_alignments, score_window [query frames], candidates (kept per\n"
      "frame), posterior_band [frames], tolerance [map frames] (the confidence is the probability of a guess\n"
      "within it of the truth), min_confidence (below: not in the map), threads, even_odds_e_value (the E-value at\n"
      "which an alignment is as likely a revisit as chance), lag (online: each frame answered once this many later\n"
      "frames have arrived, with their evidence; 0: at once), speeds (offline: the query's speeds against the map\n"
      "searched, map frames per query frame, 1 first; the others where 1 leaves frames unsure).");
  c.def(py::init([](std::size_t contrast_window, bool enhance, float contrast_offset, float gap,
                    std::optional<float> cap, float threshold, bool reverse, std::size_t max_alignments,
                    std::size_t score_window, std::size_t candidates, std::size_t posterior_band, std::size_t tolerance,
                    double min_confidence, unsigned threads, double even_odds_e_value, std::size_t lag,
                    std::vector<double> speeds) {
          LocalizeConfig config;
          config.score.contrast_window = contrast_window;
          config.enhance = enhance;
          config.score.contrast_offset = contrast_offset;
          config.search.gap = gap;
          config.search.cap = cap;
          config.significance.threshold = threshold;
          config.search.reverse = reverse;
          config.max_alignments = max_alignments;
          config.score_window = score_window;
          config.candidates = candidates;
          config.posterior_band = posterior_band;
          config.tolerance = tolerance;
          config.min_confidence = min_confidence;
          config.threads = threads;
          config.significance.max_e_value = even_odds_e_value;
          config.lag = lag;
          localize::validate_speeds(speeds);
          config.speeds = std::move(speeds);
          return config;
        }),
        py::kw_only(), py::arg("contrast_window") = d.score.contrast_window, py::arg("enhance") = d.enhance,
        py::arg("contrast_offset") = d.score.contrast_offset, py::arg("gap") = d.search.gap,
        py::arg("cap") = d.search.cap, py::arg("threshold") = d.significance.threshold,
        py::arg("reverse") = d.search.reverse, py::arg("max_alignments") = d.max_alignments,
        py::arg("score_window") = d.score_window, py::arg("candidates") = d.candidates,
        py::arg("posterior_band") = d.posterior_band, py::arg("tolerance") = d.tolerance,
        py::arg("min_confidence") = d.min_confidence, py::arg("threads") = d.threads,
        py::arg("even_odds_e_value") = d.significance.max_e_value, py::arg("lag") = d.lag, py::arg("speeds") = d.speeds)
      .def_property("contrast_window", section_getter(&LocalizeConfig::score, &align::ScoreSettings::contrast_window),
                    section_setter(&LocalizeConfig::score, &align::ScoreSettings::contrast_window))
      .def_readwrite("enhance", &LocalizeConfig::enhance)
      .def_property("contrast_offset", section_getter(&LocalizeConfig::score, &align::ScoreSettings::contrast_offset),
                    section_setter(&LocalizeConfig::score, &align::ScoreSettings::contrast_offset))
      .def_property("gap", section_getter(&LocalizeConfig::search, &align::SearchSettings::gap),
                    section_setter(&LocalizeConfig::search, &align::SearchSettings::gap))
      .def_property("cap", section_getter(&LocalizeConfig::search, &align::SearchSettings::cap),
                    section_setter(&LocalizeConfig::search, &align::SearchSettings::cap))
      .def_property("threshold", section_getter(&LocalizeConfig::significance, &align::SignificanceSettings::threshold),
                    section_setter(&LocalizeConfig::significance, &align::SignificanceSettings::threshold))
      .def_property("reverse", section_getter(&LocalizeConfig::search, &align::SearchSettings::reverse),
                    section_setter(&LocalizeConfig::search, &align::SearchSettings::reverse))
      .def_readwrite("max_alignments", &LocalizeConfig::max_alignments)
      .def_readwrite("score_window", &LocalizeConfig::score_window)
      .def_readwrite("candidates", &LocalizeConfig::candidates)
      .def_readwrite("posterior_band", &LocalizeConfig::posterior_band)
      .def_readwrite("tolerance", &LocalizeConfig::tolerance)
      .def_readwrite("min_confidence", &LocalizeConfig::min_confidence)
      .def_readwrite("threads", &LocalizeConfig::threads)
      .def_property("even_odds_e_value",
                    section_getter(&LocalizeConfig::significance, &align::SignificanceSettings::max_e_value),
                    section_setter(&LocalizeConfig::significance, &align::SignificanceSettings::max_e_value))
      .def_readwrite("lag", &LocalizeConfig::lag)
      .def_readwrite("speeds", &LocalizeConfig::speeds);
  add_repr(c, "LocalizeConfig",
           {"contrast_window", "enhance", "contrast_offset", "gap", "cap", "threshold", "reverse", "max_alignments",
            "score_window", "candidates", "posterior_band", "tolerance", "min_confidence", "threads", "lag", "speeds"});
}

void bind_strings(py::module_& m) {
  using strings::EditCosts;
  using strings::MatchConfig;
  const EditCosts dc{};
  py::class_<EditCosts> costs(
      m, "EditCosts",
      "Edit costs of algorithm A (C++ seqtopo::strings::EditCosts); the defaults are the unit costs\n"
      "of Table III ('A1'). colour_distance: None or a 16 x 16 table in [0, 1] scaling\n"
      "colour_difference.");
  costs
      .def(py::init([](double deletion, double insertion, double colour_difference, double coincidence,
                       double discordance, std::optional<strings::ColourDistanceTable> colour_distance) {
             return EditCosts{deletion, insertion, colour_difference, coincidence, discordance, colour_distance};
           }),
           py::kw_only(), py::arg("deletion") = dc.deletion, py::arg("insertion") = dc.insertion,
           py::arg("colour_difference") = dc.colour_difference, py::arg("coincidence") = dc.coincidence,
           py::arg("discordance") = dc.discordance, py::arg("colour_distance") = dc.colour_distance)
      .def_readwrite("deletion", &EditCosts::deletion)
      .def_readwrite("insertion", &EditCosts::insertion)
      .def_readwrite("colour_difference", &EditCosts::colour_difference)
      .def_readwrite("coincidence", &EditCosts::coincidence)
      .def_readwrite("discordance", &EditCosts::discordance)
      .def_readwrite("colour_distance", &EditCosts::colour_distance);
  add_repr(costs, "EditCosts", {"deletion", "insertion", "colour_difference", "coincidence", "discordance"});

  const MatchConfig d{};
  py::class_<MatchConfig> c(
      m, "MatchConfig",
      "Settings of match_strings (C++ seqtopo::strings::MatchConfig). algorithm: 'A', 'B' or 'C';\n"
      "k: maximum differences for A and B (None: no limit); costs: EditCosts (A only); cyclic:\n"
      "compare with every rotation of each database string; tie_tolerance: scores closer than\n"
      "this share a rank.");
  c.def(py::init([](const std::string& algorithm, std::optional<std::size_t> k, EditCosts costs, bool cyclic,
                    double tie_tolerance) {
          MatchConfig config;
          config.algorithm = strings::parse_algorithm(algorithm);
          config.k = limit_from_python(k);
          config.costs = std::move(costs);
          config.cyclic = cyclic;
          config.tie_tolerance = tie_tolerance;
          return config;
        }),
        py::kw_only(), py::arg("algorithm") = std::string(strings::algorithm_name(d.algorithm)),
        py::arg("k") = limit_to_python(d.k), py::arg("costs") = d.costs, py::arg("cyclic") = d.cyclic,
        py::arg("tie_tolerance") = d.tie_tolerance)
      .def_property(
          "algorithm", [](const MatchConfig& x) { return std::string(strings::algorithm_name(x.algorithm)); },
          [](MatchConfig& x, const std::string& name) { x.algorithm = strings::parse_algorithm(name); })
      .def_property(
          "k", [](const MatchConfig& x) { return limit_to_python(x.k); },
          [](MatchConfig& x, std::optional<std::size_t> k) { x.k = limit_from_python(k); })
      .def_readwrite("costs", &MatchConfig::costs)
      .def_readwrite("cyclic", &MatchConfig::cyclic)
      .def_readwrite("tie_tolerance", &MatchConfig::tie_tolerance);
  add_repr(c, "MatchConfig", {"algorithm", "k", "costs", "cyclic", "tie_tolerance"});

  m.def(
      "preset_costs", &strings::preset_costs, py::arg("name"),
      "The paper's named cost tables: 'A1' (Table III), 'A2-rooms', 'A2-ground-floor', 'A2-white-hall', 'A2-global'.");
  m.def("preset_names", &strings::preset_names, "Names accepted by preset_costs.");
}

void bind_kappa(py::module_& m) {
  using similarity::KappaRule;
  const KappaRule d{};
  py::class_<KappaRule> c(m, "KappaRule",
                          "The automatic kappa of S = 1 - kappa * D (C++ seqtopo::similarity::KappaRule): about\n"
                          "matches_per_image partners per image get S > 0, among pairs at least min_separation apart.");
  c.def(
       py::init([](double matches_per_image, std::size_t min_separation, double max_fraction, std::size_t max_samples) {
         return KappaRule{matches_per_image, min_separation, max_fraction, max_samples};
       }),
       py::kw_only(), py::arg("matches_per_image") = d.matches_per_image, py::arg("min_separation") = d.min_separation,
       py::arg("max_fraction") = d.max_fraction, py::arg("max_samples") = d.max_samples)
      .def_readwrite("matches_per_image", &KappaRule::matches_per_image)
      .def_readwrite("min_separation", &KappaRule::min_separation)
      .def_readwrite("max_fraction", &KappaRule::max_fraction)
      .def_readwrite("max_samples", &KappaRule::max_samples);
  add_repr(c, "KappaRule", {"matches_per_image", "min_separation", "max_fraction", "max_samples"});
}

}  // namespace

void bind_configs(py::module_& m) {
  bind_align(m);
  bind_map(m);
  bind_localize(m);
  bind_strings(m);
  bind_kappa(m);
}

}  // namespace seqtopo::python
