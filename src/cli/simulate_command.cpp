// seqtopo simulate: synthetic worlds with exact ground truth (INTERFACE.md, docs/simulator.md).
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>

#include "command_registry.hpp"
#include "options/number_options.hpp"
#include "progress.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/plot/png.hpp"
#include "seqtopo/simulator/scenarios.hpp"

namespace seqtopo::cli::simulate_command {
namespace {

struct SimulateOptions {
  std::string scenario, out;
  bool list = false, no_images = false;
  std::uint64_t seed = 1;
  std::optional<double> interval, heading_drift, scale_error, zigzag;
  double odometry_noise = 1.0, pixel_noise = 2.0, lighting_change = 1.0;
  int panorama_width = 360, panorama_height = 60, image_width = 160, image_height = 120, supersample = 2;
  double place_length = 1.5, junction_radius = 0.75;
  double gt_radius = 1.0, gt_band_metres = 5.0;
  std::optional<std::size_t> gt_band;
  std::size_t max_frames = 0;
  unsigned threads = 0;
};

std::string frame_name(std::size_t k) { return fmt::format("{:05d}.png", k); }

std::string poses_csv(const std::vector<simulator::Pose2>& poses) {
  std::string text = "index,x,y,theta\n";
  for (std::size_t k = 0; k < poses.size(); ++k) {
    text += fmt::format("{},{:.6f},{:.6f},{:.6f}\n", k, poses[k].x, poses[k].y, poses[k].theta);
  }
  return text;
}

// Encodes the images on all threads, then writes them into one staged folder.
void write_images(io::OutputDirectory& out, const std::string& folder, const std::vector<RgbImage>& images,
                  const std::vector<std::string>& names, int threads, Progress& progress) {
  std::vector<std::string> encoded(images.size());
  const auto n = static_cast<std::ptrdiff_t>(images.size());
  std::atomic<std::size_t> done{0};
#pragma omp parallel for schedule(dynamic) num_threads(threads)
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    encoded[static_cast<std::size_t>(k)] = plot::encode_png(images[static_cast<std::size_t>(k)]);
    progress.advance(++done, images.size(), folder + " encoded");
  }
  const std::filesystem::path dir = out.staged(folder);
  std::filesystem::create_directories(dir);
  for (std::size_t k = 0; k < images.size(); ++k) {
    std::ofstream file(dir / names[k], std::ios::binary | std::ios::trunc);
    file.write(encoded[k].data(), static_cast<std::streamsize>(encoded[k].size()));
    if (!file) throw InputError((out.dir() / folder / names[k]).string(), "write failed");
  }
}

void list_scenarios() {
  for (const auto& s : simulator::scenarios()) {
    std::cout << fmt::format("{:<17} {:<9} {}\n", s.name,
                             s.kind == simulator::ScenarioKind::sequence ? "sequence" : "survey", s.description);
  }
}

void run(const SimulateOptions& o) {
  if (o.list) {
    list_scenarios();
    return;
  }
  if (o.scenario.empty()) throw InputError("--scenario", "name a scenario (see --list)");
  if (o.out.empty()) throw InputError("--out", "give an output directory");
  bool known = false;
  for (const auto& s : simulator::scenarios()) known = known || s.name == o.scenario;
  if (!known) throw InputError("--scenario", fmt::format("unknown scenario '{}' (see --list)", o.scenario));
  if (o.interval && !(*o.interval > 0)) throw InputError("--interval", "must be > 0");
  if (o.odometry_noise < 0) throw InputError("--odometry-noise", "must be >= 0");
  if (o.pixel_noise < 0) throw InputError("--pixel-noise", "must be >= 0");
  if (o.lighting_change < 0) throw InputError("--lighting-change", "must be >= 0");
  if (o.panorama_width < 8 || o.panorama_height < 2)
    throw InputError("--panorama-width/--panorama-height", "too small");
  if (o.image_width < 8 || o.image_height < 2) throw InputError("--image-width/--image-height", "too small");
  if (o.supersample < 1 || o.supersample > 8) throw InputError("--supersample", "must be in 1..8");
  if (!(o.place_length > 0)) throw InputError("--place-length", "must be > 0");
  if (o.junction_radius < 0) throw InputError("--junction-radius", "must be >= 0");
  if (!(o.gt_radius > 0)) throw InputError("--gt-radius", "must be > 0");

  simulator::SimulationConfig config;
  config.seed = o.seed;
  config.interval = o.interval;
  config.odometry_noise = o.odometry_noise;
  config.heading_drift = o.heading_drift;
  config.scale_error = o.scale_error;
  config.zigzag_amplitude = o.zigzag;
  config.panorama.width = o.panorama_width;
  config.panorama.height = o.panorama_height;
  config.panorama.supersample = o.supersample;
  config.camera.width = o.image_width;
  config.camera.height = o.image_height;
  config.camera.supersample = o.supersample;
  config.forward_images = !o.no_images;
  config.pixel_noise = o.pixel_noise;
  config.lighting_change = o.lighting_change;
  config.places.place_length = o.place_length;
  config.places.junction_radius = o.junction_radius;
  config.max_frames = o.max_frames;
  const int threads = static_cast<int>(resolve_threads(o.threads));
  config.threads = threads;

  io::OutputDirectory out(o.out, {.inputs = {}, .command = "seqtopo simulate"});
  const auto started = std::chrono::steady_clock::now();
  Progress progress("seqtopo simulate");
  progress.plan({"world", "rendering", "files"});
  progress.begin("world");
  const simulator::ScenarioSetup setup = simulator::build_scenario(o.scenario, config);
  progress.end();
  progress.begin("rendering");
  const simulator::SimulatedRun result = simulator::simulate(setup, config);
  progress.end();
  const double render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  progress.begin("files");
  std::string summary;
  if (result.kind == simulator::ScenarioKind::survey) {
    std::vector<std::string> names;
    std::string points = "id,role,x,y,place\n";
    for (const auto& p : result.points) {
      names.push_back(p.id + ".png");
      points += fmt::format("{},{},{:.6f},{:.6f},{}\n", p.id, p.map ? "map" : "test", p.pose.x, p.pose.y, p.place);
    }
    std::string adjacency = "test_id,map_id\n";
    for (const auto& [t, m] : result.adjacency) {
      adjacency += fmt::format("{},{}\n", result.points[static_cast<std::size_t>(t)].id,
                               result.points[static_cast<std::size_t>(m)].id);
    }
    write_images(out, "panoramas", result.panoramas, names, threads, progress);
    out.write("points.csv", points);
    out.write("adjacency.csv", adjacency);
    const auto maps = std::count_if(result.points.begin(), result.points.end(), [](const auto& p) { return p.map; });
    out.write("simulation.json",
              fmt::format("{{\"scenario\": \"{}\", \"seed\": {}, \"map_points\": {}, \"test_points\": {}}}\n",
                          result.scenario, o.seed, maps, result.points.size() - static_cast<std::size_t>(maps)));
    summary = fmt::format("{} map and {} test points", maps, result.points.size() - static_cast<std::size_t>(maps));
  } else {
    const std::size_t n = result.poses.size();
    std::vector<std::string> names;
    for (std::size_t k = 0; k < n; ++k) names.push_back(frame_name(k));
    write_images(out, "panoramas", result.panoramas, names, threads, progress);
    if (!result.images.empty()) write_images(out, "images", result.images, names, threads, progress);
    out.write("odometry.csv", poses_csv(result.odometry));
    out.write("poses.csv", poses_csv(result.poses));
    std::string places = "index,place\n";
    for (std::size_t k = 0; k < n; ++k) places += fmt::format("{},{}\n", k, result.places[k]);
    out.write("places.csv", places);
    std::string junctions = "place\n";
    for (int j : result.junctions) junctions += fmt::format("{}\n", j);
    out.write("junctions.csv", junctions);
    const std::size_t band =
        o.gt_band.value_or(static_cast<std::size_t>(std::ceil(o.gt_band_metres / result.interval - 1e-9)));
    const auto truth = simulator::same_place_matrix(result, o.gt_radius, band);
    RgbImage truth_image(static_cast<int>(n), static_cast<int>(n));
    for (std::size_t k = 0; k < truth.values.size(); ++k) {
      std::fill_n(truth_image.pixels.begin() + static_cast<std::ptrdiff_t>(3 * k), 3, truth.values[k]);
    }
    if (n > 0) out.write("ground_truth.png", plot::encode_png(truth_image));
    std::size_t pairs = 0;
    for (auto v : truth.values) pairs += v != 0 ? 1 : 0;
    out.write("simulation.json",
              fmt::format("{{\"scenario\": \"{}\", \"seed\": {}, \"frames\": {}, \"interval\": {}, \"places\": {}, "
                          "\"junctions\": {}, \"gt_radius\": {}, \"gt_band\": {}, \"gt_pairs\": {}}}\n",
                          result.scenario, o.seed, n, result.interval,
                          result.places.empty() ? 0 : *std::max_element(result.places.begin(), result.places.end()) + 1,
                          result.junctions.size(), o.gt_radius, band, pairs / 2));
    summary = fmt::format("{} frames every {} m, {} ground-truth pairs (radius {} m, band {} frames)", n,
                          result.interval, pairs / 2, o.gt_radius, band);
  }
  out.write("floor_plan.png", plot::encode_png(result.floor_plan));
  out.commit();
  progress.end();
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  progress.line(fmt::format("{}: {}; rendered in {:.2f} s, written in {:.2f} s -> {}", o.scenario, summary,
                            render_seconds, total - render_seconds, o.out));
}

const RegisterCommand registered{
    {"simulate", "Synthetic worlds with exact ground truth: panoramas, camera images, odometry, poses, places",
     [](CLI::App& app) {
       auto o = std::make_shared<SimulateOptions>();
       app.add_option("--scenario", o->scenario, "scenario name (see --list)");
       app.add_option("--out", o->out, "output directory");
       app.add_flag("--list", o->list, "list the scenarios and exit");
       add_number(app, "--seed", o->seed, kNonNegative, "seed of the world's decoration and of all noise");
       add_number(app, "--interval", o->interval, kPositive,
                  "travel between frames [m] (default per scenario: 0.25 indoors, 0.5 outdoors)");
       add_number(app, "--odometry-noise", o->odometry_noise, kNonNegative,
                  "factor on the scenario's odometry drift and noise (0 = exact)");
       add_number(app, "--heading-drift", o->heading_drift, kAnyFinite,
                  "systematic odometry heading drift [rad/m] (either sign)");
       add_number(app, "--scale-error", o->scale_error, {.min = -1, .min_exclusive = true},
                  "systematic odometry scale error (0.01 = reads 1 % long, -0.01 = 1 % short)");
       add_number(app, "--zigzag-amplitude", o->zigzag, kNonNegative,
                  "amplitude of the zigzag scenario's zig-zagging traversal [m]");
       add_number(app, "--panorama-width", o->panorama_width, {.min = 8, .max = 16384},
                  "panorama width [pixels] = 360 degrees");
       add_number(app, "--panorama-height", o->panorama_height, {.min = 2, .max = 4096},
                  "panorama height [pixels] (elevation -30..+30 degrees)");
       add_number(app, "--image-width", o->image_width, {.min = 8, .max = 8192},
                  "forward camera width [pixels] (60 degree field of view)");
       add_number(app, "--image-height", o->image_height, {.min = 2, .max = 8192}, "forward camera height [pixels]");
       app.add_flag("--no-images", o->no_images, "skip the forward camera (panoramas only)");
       add_number(app, "--supersample", o->supersample, {.min = 1, .max = 8},
                  "rays per pixel along each axis (anti-aliasing)");
       add_number(app, "--pixel-noise", o->pixel_noise, kNonNegative, "sensor noise, standard deviation [grey levels]");
       add_number(app, "--lighting-change", o->lighting_change, kNonNegative,
                  "factor on the lighting differences between traversals (0 = same lighting)");
       add_number(app, "--place-length", o->place_length, kPositive, "length of a ground-truth place along a path [m]");
       add_number(app, "--junction-radius", o->junction_radius, kNonNegative,
                  "stretch of path around a node that is the node's place [m]");
       add_number(app, "--gt-radius", o->gt_radius, kPositive,
                  "ground_truth.png: same place when path points are within R [m]");
       add_number(app, "--gt-band", o->gt_band, kNonNegative,
                  "ground_truth.png: pairs with |i - j| < B frames are zero (default: 5 m of travel)");
       add_number(app, "--max-frames", o->max_frames, kNonNegative, "keep only the first N frames (0 = all)");
       add_number(app, "--threads", o->threads, kThreads, "worker threads (0 = all cores)");
       app.callback([o] { run(*o); });
     }}};

}  // namespace
}  // namespace seqtopo::cli::simulate_command
