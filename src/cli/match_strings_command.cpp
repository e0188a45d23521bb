// seqtopo match-strings: string-matching localization (INTERFACE.md, González-Buesa & Campos).
#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "command_registry.hpp"
#include "options/number_options.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/text_file.hpp"
#include "seqtopo/core/version.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/io/csv.hpp"
#include "seqtopo/strings/localization.hpp"
#include "seqtopo/strings/strings_file.hpp"

namespace seqtopo::cli::match_strings_command {
namespace {

struct MatchStringsOptions {
  std::string db_path, queries_path, adjacency_path, out_dir = "seqtopo-out";
  std::string algorithm = "A", preset = "A1";
  std::optional<std::size_t> k;
  std::optional<double> deletion, insertion, colour_difference, coincidence, discordance;
  bool cyclic = false;
  std::size_t window = 1;
};

std::vector<strings::StringRecord> read_strings(const std::string& path) {
  try {
    auto records = strings::parse_strings_tsv(read_text_file(path, "strings file"));
    if (records.empty()) throw InputError(path, "no string record");
    return records;
  } catch (const strings::StringsFileError& e) {
    throw InputError(fmt::format("{}:{}", path, e.line()), e.what());
  }
}

// `test_id,map_id` pairs (header first); ids must name a query and a database record.
std::vector<std::vector<bool>> read_adjacency(const std::string& path,
                                              const std::map<std::string, std::size_t>& queries,
                                              const std::map<std::string, std::size_t>& db) {
  std::vector<std::vector<bool>> adjacent(queries.size(), std::vector<bool>(db.size(), false));
  for (const auto& row : io::read_csv(path, {"test_id", "map_id"})) {
    const auto q = queries.find(row.fields[0]);
    const auto d = db.find(row.fields[1]);
    // Pairs naming points of another data set (e.g. a map point absent from this database) are skipped.
    if (q == queries.end() || d == db.end()) continue;
    adjacent[q->second][d->second] = true;
  }
  return adjacent;
}

nlohmann::json rates_json(const strings::Rates& r) {
  return {{"total", r.total},
          {"exact", r.exact},
          {"correct", r.correct},
          {"wrong", r.wrong},
          {"exact_percent", r.percent(r.exact)},
          {"correct_percent", r.percent(r.correct)},
          {"wrong_percent", r.percent(r.wrong)}};
}

// The paper's table. The geometric rates are over the topologically correct test points only (a point placed in
// the wrong place has no geometric score), which the table says when they are fewer than all.
std::string metrics_table(const strings::LocalizationMetrics& m, const std::string& title, std::size_t test_points) {
  std::string out = title + "\n";
  auto rows = [&](const char* kind, const strings::Rates& r, const std::string& of) {
    out += fmt::format("{} exact   {:6.1f} %\n", kind, r.percent(r.exact));
    out += fmt::format("{} correct {:6.1f} %\n", kind, r.percent(r.correct));
    out += fmt::format("{} wrong   {:6.1f} %   ({})\n", kind, r.percent(r.wrong), of);
  };
  if (m.topological) rows("Top. ", *m.topological, fmt::format("of {} test points", m.topological->total));
  if (m.geometric) {
    const auto& g = *m.geometric;
    rows("Geom.", g,
         g.total == test_points ? fmt::format("of {} test points", g.total)
                                : fmt::format("of {} of the {} test points: the topologically correct ones{}", g.total,
                                              test_points, m.topological ? "" : " with a position"));
  }
  return out;
}

void run(const MatchStringsOptions& o) {
  strings::MatchConfig config;
  try {
    config.algorithm = strings::parse_algorithm(o.algorithm);
  } catch (const std::invalid_argument& e) {
    throw InputError("--algorithm", e.what());
  }
  try {
    config.costs = strings::preset_costs(o.preset);
  } catch (const std::invalid_argument& e) {
    throw InputError("--preset", e.what());
  }
  if (o.deletion) config.costs.deletion = *o.deletion;
  if (o.insertion) config.costs.insertion = *o.insertion;
  if (o.colour_difference) config.costs.colour_difference = *o.colour_difference;
  if (o.coincidence) config.costs.coincidence = *o.coincidence;
  if (o.discordance) config.costs.discordance = *o.discordance;
  try {
    strings::validate(config.costs);
  } catch (const std::invalid_argument& e) {
    throw InputError("--preset/--*-cost", e.what());
  }
  if (o.k) config.k = *o.k;
  config.cyclic = o.cyclic;
  if (o.window == 0) throw InputError("--window", "must be >= 1");

  io::OutputDirectory out(
      o.out_dir, {.inputs = {o.db_path, o.queries_path, o.adjacency_path}, .command = "seqtopo match-strings"});
  const auto db = read_strings(o.db_path);
  const auto queries = read_strings(o.queries_path);
  std::vector<std::string> db_strings, query_strings;
  std::map<std::string, std::size_t> db_index, query_index;
  for (const auto& r : db) db_index[r.id] = db_strings.size(), db_strings.push_back(r.symbols);
  for (const auto& r : queries) query_index[r.id] = query_strings.size(), query_strings.push_back(r.symbols);

  const auto matches = strings::match_all_windowed(db_strings, query_strings, config, o.window);

  // With --cyclic a fifth column gives the rotation (in symbols) of the database string that matched best.
  // The header is the first line (the settings are in metrics.json and on the command line, not in a comment).
  std::string tsv = fmt::format("query_id\trank\tdb_id\tscore{}\n", o.cyclic ? "\trotation" : "");
  for (std::size_t q = 0; q < matches.size(); ++q) {
    for (const auto& c : matches[q].ranked) {
      tsv += fmt::format("{}\t{}\t{}\t{:.6g}", queries[q].id, c.rank, db[c.db_index].id, c.score);
      tsv += o.cyclic ? fmt::format("\t{}\n", c.rotation) : "\n";
    }
  }
  out.write("matches.tsv", tsv);

  // Ground truth: adjacency from --adjacency or shared place labels; positions from the x, y columns.
  strings::GroundTruth truth;
  const bool places = std::all_of(db.begin(), db.end(), [](const auto& r) { return r.place.has_value(); }) &&
                      std::all_of(queries.begin(), queries.end(), [](const auto& r) { return r.place.has_value(); });
  if (!o.adjacency_path.empty()) {
    truth.adjacent = read_adjacency(o.adjacency_path, query_index, db_index);
  } else if (places) {
    truth.adjacent.assign(queries.size(), std::vector<bool>(db.size(), false));
    for (std::size_t q = 0; q < queries.size(); ++q) {
      for (std::size_t d = 0; d < db.size(); ++d) truth.adjacent[q][d] = *queries[q].place == *db[d].place;
    }
  }
  const bool positions = std::any_of(db.begin(), db.end(), [](const auto& r) { return r.x.has_value(); }) &&
                         std::any_of(queries.begin(), queries.end(), [](const auto& r) { return r.x.has_value(); });
  if (positions) {
    auto point = [](const strings::StringRecord& r) -> std::optional<strings::Point2> {
      if (!r.x) return std::nullopt;
      return strings::Point2{*r.x, *r.y};
    };
    for (const auto& r : db) truth.db_positions.push_back(point(r));
    for (const auto& r : queries) truth.query_positions.push_back(point(r));
  }
  const auto metrics = strings::score_localization(matches, truth);
  if (metrics.topological || metrics.geometric) {
    nlohmann::json j = {{"seqtopo_version", std::string(version())},
                        {"algorithm", o.algorithm},
                        {"cyclic", o.cyclic},
                        {"window", o.window},
                        {"queries", queries.size()},
                        {"database", db.size()}};
    if (o.k) j["k"] = *o.k;
    if (config.algorithm == strings::Algorithm::A) {
      j["costs"] = {{"deletion", config.costs.deletion},
                    {"insertion", config.costs.insertion},
                    {"colour_difference", config.costs.colour_difference},
                    {"coincidence", config.costs.coincidence},
                    {"discordance", config.costs.discordance}};
    }
    if (metrics.topological) j["topological"] = rates_json(*metrics.topological);
    if (metrics.geometric) j["geometric"] = rates_json(*metrics.geometric);
    out.write("metrics.json", j.dump(1) + "\n");
    const std::string table =
        metrics_table(metrics, fmt::format("algorithm {}{}", o.algorithm, o.cyclic ? " (cyclic)" : ""), queries.size());
    out.write("metrics.txt", table);
    std::cout << table;
  }
  out.commit();
  std::size_t best_total = 0;
  for (const auto& m : matches) best_total += m.best().size();
  std::cerr << fmt::format(
      "seqtopo match-strings: {} queries x {} database strings, {:.2f} best matchings per query\n", queries.size(),
      db.size(), queries.empty() ? 0.0 : static_cast<double>(best_total) / static_cast<double>(queries.size()));
}

const RegisterCommand registered{
    {"match-strings",
     "String-matching localization: every query fingerprint against every database fingerprint (algorithm A, B or C)",
     [](CLI::App& app) {
       auto o = std::make_shared<MatchStringsOptions>();
       app.add_option("--db", o->db_path, "database strings (map points): id<TAB>string[<TAB>x<TAB>y[<TAB>place]]")
           ->required()
           ->check(CLI::ExistingFile);
       app.add_option("--queries", o->queries_path, "query strings (test points), same format")
           ->required()
           ->check(CLI::ExistingFile);
       app.add_option("--algorithm", o->algorithm,
                      "A = global alignment with <= k differences (weighted costs), B = k-differences inexact matching "
                      "(Landau-Vishkin), C = longest common subsequence (Hunt-Szymanski)")
           ->capture_default_str();
       add_number(app, "--k", o->k, kNonNegative, "maximum number of differences for A and B (default: no limit)");
       app.add_option("--preset", o->preset,
                      "cost table for A: A1, A2-rooms, A2-ground-floor, A2-white-hall, A2-global")
           ->capture_default_str();
       add_number(app, "--deletion-cost", o->deletion, kNonNegative,
                  "cost of deleting a query symbol (overrides the preset)");
       add_number(app, "--insertion-cost", o->insertion, kNonNegative,
                  "cost of inserting a database symbol (overrides the preset)");
       add_number(app, "--colour-difference-cost", o->colour_difference, kNonNegative,
                  "cost of two different colour patches (overrides the preset)");
       add_number(app, "--coincidence-cost", o->coincidence, kAnyFinite,
                  "cost of two equal symbols, may be negative (overrides the preset)");
       add_number(app, "--discordance-cost", o->discordance, kNonNegative,
                  "cost of an edge against a colour patch (overrides the preset)");
       app.add_flag("--cyclic", o->cyclic,
                    "panoramas: compare with every rotation of each database string (heading unknown)");
       add_number(app, "--window", o->window, kAtLeastOne,
                  "localize each query with the W queries ending at it, along a monotone chain of database points "
                  "(both files in travel order)");
       app.add_option("--adjacency", o->adjacency_path,
                      "CSV test_id,map_id of adjacent points (default: same place label)")
           ->check(CLI::ExistingFile);
       app.add_option("--out", o->out_dir,
                      "output folder: matches.tsv, and metrics.json + metrics.txt with ground truth")
           ->capture_default_str();
       app.callback([o] { run(*o); });
     }}};

}  // namespace
}  // namespace seqtopo::cli::match_strings_command
