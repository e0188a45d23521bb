// seqtopo fingerprint: panoramic images -> fingerprint strings (INTERFACE.md, "Strings files").
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "command_registry.hpp"
#include "options/number_options.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/parse_number.hpp"
#include "seqtopo/fingerprint/fingerprint.hpp"
#include "seqtopo/image/image_io.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/io/csv.hpp"
#include "seqtopo/pipeline/sequence_input.hpp"
#include "seqtopo/strings/strings_file.hpp"

namespace seqtopo::cli::fingerprint_command {
namespace {

struct FingerprintOptions {
  std::vector<std::string> inputs;
  std::string out_path = "-", positions_path, role;
  fingerprint::FingerprintConfig config;
};

struct PointRow {
  std::string role, place;
  double x = 0.0, y = 0.0;
};

// points.csv as the simulator writes it: header id,role,x,y,place.
std::map<std::string, PointRow> read_points(const std::string& path) {
  std::map<std::string, PointRow> rows;
  for (const auto& r : io::read_csv(path, {"id", "role", "x", "y", "place"})) {
    const auto& f = r.fields;
    PointRow row{f[1], f[4]};
    row.x = parse_number<double>(r.where + " (x)", f[2]);
    row.y = parse_number<double>(r.where + " (y)", f[3]);
    if (f[0].empty() || row.place.empty()) throw InputError(r.where, "empty id or place");
    if (!rows.emplace(f[0], row).second) throw InputError(r.where, "repeated id '" + f[0] + "'");
  }
  return rows;
}

void run(const FingerprintOptions& o) {
  if (!o.role.empty() && o.positions_path.empty()) throw InputError("--role", "needs --positions");
  std::vector<std::filesystem::path> files;
  for (const auto& input : o.inputs) {
    if (std::filesystem::is_directory(input)) {
      const auto listed = pipeline::list_images(input);
      files.insert(files.end(), listed.begin(), listed.end());
    } else if (std::filesystem::exists(input)) {
      files.emplace_back(input);
    } else {
      throw InputError(input, "no such file or folder");
    }
  }
  std::map<std::string, PointRow> points;
  if (!o.positions_path.empty()) points = read_points(o.positions_path);

  std::vector<strings::StringRecord> records;
  std::map<std::string, std::string> seen;
  for (const auto& file : files) {
    strings::StringRecord r;
    r.id = file.stem().string();
    if (!o.positions_path.empty()) {
      const auto it = points.find(r.id);
      if (it == points.end()) throw InputError(o.positions_path, "no row for image '" + file.string() + "'");
      if (!o.role.empty() && it->second.role != o.role) continue;
      r.x = it->second.x;
      r.y = it->second.y;
      r.place = it->second.place;
    }
    if (const auto [it, fresh] = seen.emplace(r.id, file.string()); !fresh) {
      throw InputError(file.string(), "same id '" + r.id + "' as " + it->second);
    }
    try {
      r.symbols = fingerprint::extract_fingerprint(image::load_image(file), o.config).symbols;
    } catch (const std::invalid_argument& e) {
      throw InputError(file.string(), e.what());
    }
    records.push_back(std::move(r));
  }
  if (records.empty()) throw InputError("IMAGES", o.role.empty() ? "no image" : "no image with role '" + o.role + "'");
  const std::string text = strings::format_strings_tsv(
      records, "id<TAB>fingerprint ('v' vertical edge, 'A'..'P' colour patch)[<TAB>x<TAB>y<TAB>place]");
  if (o.out_path == "-") {
    std::cout << text;
  } else {
    io::write_file_atomic(o.out_path, text);
  }
  std::cerr << fmt::format("seqtopo fingerprint: {} panorama(s)\n", records.size());
}

const RegisterCommand registered{
    {"fingerprint",
     "Panoramic images -> fingerprint strings: 'v' = vertical edge, 'A'..'P' = colour patch, in angular order",
     [](CLI::App& app) {
       auto o = std::make_shared<FingerprintOptions>();
       app.add_option("IMAGES", o->inputs, "panoramas (360 degrees across the width): files or folders (natural order)")
           ->required();
       app.add_option("--out", o->out_path, "output strings file F.tsv ('-' = standard output)")->capture_default_str();
       app.add_option("--positions", o->positions_path,
                      "CSV id,role,x,y,place (e.g. the simulator's points.csv): adds x, y, place")
           ->check(CLI::ExistingFile);
       app.add_option("--role", o->role, "keep only the images of this role in --positions (map or test)");
       auto& c = o->config;
       add_number(app, "--edge-step", c.edge_step, kPositive, "vertical edge: brightness step [grey levels]");
       add_number(app, "--edge-fraction", c.edge_min_fraction, {.min = 0, .max = 1, .min_exclusive = true},
                  "vertical edge: fraction of band rows with the step");
       add_number(app, "--min-patch-width", c.min_patch_width, kAtLeastOne, "colour patch: minimum width [columns]");
       add_number(app, "--saturation-min", c.saturation_min, {.min = 0, .max = 1},
                  "colour classes: below this saturation a pixel is grey");
       add_number(app, "--brightness-percentile", c.brightness_percentile, {.min = 0, .max = 1},
                  "colour classes: scale brightness so this percentile of the band reaches a fixed level (0 = off)");
       app.callback([o] { run(*o); });
     }}};

}  // namespace
}  // namespace seqtopo::cli::fingerprint_command
