#include "report_data.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include "seqtopo/core/version.hpp"
#include "seqtopo/image/image_io.hpp"
#include "seqtopo/plot/matrix_image.hpp"
#include "seqtopo/plot/png.hpp"
#ifdef SEQTOPO_HAVE_RECORDING
#include "seqtopo/recording/recording.hpp"
#endif
#include "seqtopo/report/interactive.hpp"

namespace seqtopo::outputs::detail {

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

nlohmann::json loop_closure_metrics_json(const evaluation::LoopClosureMetrics& m) {
  return {{"tp", m.tp},         {"fp", m.fp}, {"fn", m.fn},   {"precision", m.precision},
          {"recall", m.recall}, {"f1", m.f1}, {"auc", m.auc}, {"recall_at_100_precision", m.recall_at_100_precision}};
}
namespace {

std::string jpeg_uri(const std::string& jpeg) { return "data:image/jpeg;base64," + report::base64(jpeg); }

std::string thumbnail_uri(const RgbImage& image, int side) {
  return jpeg_uri(plot::encode_jpeg(plot::shrink(image, side), 75));
}

}  // namespace

nlohmann::json sequence_json(const pipeline::SequenceInput& input, std::size_t frames,
                             const std::vector<std::size_t>& wanted, const std::string& noun,
                             const std::vector<std::string>* jpegs) {
  nlohmann::json s = {{"count", frames}, {"noun", noun}};
  std::vector<std::string> names(frames);
  nlohmann::json thumbs = nlohmann::json::array();
  for (std::size_t k = 0; k < frames; ++k) thumbs.push_back(nullptr);
  // Which frames get one: all of them, or the wanted ones first.
  std::vector<bool> embed(frames, frames <= kMaxThumbnails);
  if (frames > kMaxThumbnails) {
    std::size_t budget = kMaxThumbnails;
    for (auto k : wanted) {
      if (k < frames && !embed[k] && budget > 0) embed[k] = true, --budget;
    }
  }
  const int side = report_thumbnail_side(frames);
  std::string note;
  if (input.path.empty()) {
    note = "no images: the sequence was given in memory, or as several sessions";
  } else {
    try {
      switch (pipeline::resolve_input_kind(input)) {
        case pipeline::InputKind::images: {
          const auto files = pipeline::list_input_images(input).files;
          if (files.size() != frames) {
            note = fmt::format("no images: the folder has {} images, the run {} frames", files.size(), frames);
            break;
          }
          std::vector<std::string> uris(frames);
          if (jpegs != nullptr && jpegs->size() == frames) {  // made when the run read the images
            for (std::size_t k = 0; k < frames; ++k) {
              names[k] = files[k].filename().string();
              if (embed[k] && !(*jpegs)[k].empty()) thumbs[k] = jpeg_uri((*jpegs)[k]);
            }
            break;
          }
          // Decoding the images is most of the report's time: on every core, each thread its own frames.
          const unsigned workers = std::max(1U, std::min(8U, std::thread::hardware_concurrency()));
          std::vector<std::thread> pool;
          std::exception_ptr failure;
          std::mutex failure_mutex;
          for (unsigned w = 0; w < workers; ++w) {
            pool.emplace_back([&, w] {
              try {
                for (std::size_t k = w; k < frames; k += workers) {
                  if (embed[k]) uris[k] = thumbnail_uri(image::load_image(files[k]), side);
                }
              } catch (...) {
                const std::lock_guard lock(failure_mutex);
                failure = std::current_exception();
              }
            });
          }
          for (auto& t : pool) t.join();
          if (failure) std::rethrow_exception(failure);
          for (std::size_t k = 0; k < frames; ++k) {
            names[k] = files[k].filename().string();
            if (embed[k]) thumbs[k] = std::move(uris[k]);
          }
          break;
        }
        case pipeline::InputKind::video:
          image::for_each_video_frame(input.path, input.every, [&](std::size_t k, const RgbImage& frame) {
            if (k < frames && embed[k]) thumbs[k] = thumbnail_uri(frame, side);
          });
          for (std::size_t k = 0; k < frames; ++k) names[k] = fmt::format("frame {}", k * input.every);
          break;
        case pipeline::InputKind::bag: {
#ifdef SEQTOPO_HAVE_RECORDING
          const recording::Recording bag(input.path);
          std::size_t kept = 0;  // the callback's index counts the topic's messages, not the kept frames
          bag.for_each_image(bag.image_topic(input.image_topic), input.every, input.frames,
                             [&](std::size_t message, double, const RgbImage& frame) {
                               if (kept < frames) {
                                 if (embed[kept]) thumbs[kept] = thumbnail_uri(frame, side);
                                 names[kept] = fmt::format("message {}", message);
                               }
                               ++kept;
                             });
#else
          note = "no images: this seqtopo was built without bag support";
#endif
          break;
        }
        case pipeline::InputKind::descriptors:
          note = "no images: the input is a descriptors.npy (one row per " + noun + ")";
          break;
        default:
          note = "no images: the input is a similarity matrix";
      }
    } catch (const std::exception& e) {
      note = std::string("no images: ") + e.what();
      for (auto& t : thumbs) t = nullptr;
    }
  }
  if (frames > kMaxThumbnails && note.empty()) {
    note = fmt::format("no thumbnail: the report embeds {} of the {} {}s (those in pairs first)", kMaxThumbnails,
                       frames, noun);
  }
  s["names"] = names;
  s["thumbnails"] = std::move(thumbs);
  s["note"] = note;
  s["thumbnail_side"] = side;
  return s;
}

nlohmann::json matrix_json(const DenseMatrix<float>& cells, std::size_t rows, std::size_t cols,
                           const std::string& row_label, const std::string& col_label, const std::string& value_label) {
  const plot::ValueRange range = plot::display_range(cells, true);
  // A large matrix of noisy scores compresses badly as PNG (4 MB at 2048 x 2048); as a JPEG it is a quarter.
  const bool large = std::max(cells.rows, cells.cols) > 1024;
  const std::string image = large ? plot::matrix_grey_jpeg(cells, range) : plot::matrix_grey_png(cells, range);
  return {{"image", std::string(large ? "data:image/jpeg;base64," : "data:image/png;base64,") + report::base64(image)},
          {"rows", rows},
          {"cols", cols},
          {"range", {range.lo, range.hi}},
          {"row_label", row_label},
          {"col_label", col_label},
          {"value_label", value_label}};
}

nlohmann::json alignment_json(const align::LocalAlignment& a, std::size_t id, bool kept) {
  nlohmann::json path = nlohmann::json::array();
  const std::size_t step = std::max<std::size_t>(1, (a.pairs.size() + 399) / 400);
  for (std::size_t k = 0; k < a.pairs.size(); k += step) path.push_back({a.pairs[k].first, a.pairs[k].second});
  if (!a.pairs.empty() && (a.pairs.size() - 1) % step != 0)
    path.push_back({a.pairs.back().first, a.pairs.back().second});
  return {{"id", id},
          {"direction", std::string(align::to_string(a.direction))},
          {"kept", kept},
          {"score", a.score},
          {"a", {a.a_begin, a.a_end}},
          {"b", {a.b_begin, a.b_end}},
          {"pairs", a.pairs.size()},
          {"path", std::move(path)}};
}

nlohmann::json calibration_json(const evaluation::Calibration& c, const char* count_name) {
  nlohmann::json bins = nlohmann::json::array();
  for (const auto& b : c.bins) {
    bins.push_back({{"lower", b.lower},
                    {"upper", b.upper},
                    {"count", b.count},
                    {"mean_confidence", b.mean_confidence},
                    {"accuracy", b.accuracy}});
  }
  return {{"ece", c.ece}, {count_name, c.detections}, {"bins", bins}};
}

void provenance(report::HtmlReport& html, const ReportOptions& options) {
  std::string text = "<p class=\"provenance\">seqtopo " + report::escape_html(std::string(version()));
  if (!options.command_line.empty()) text += ", run as <code>" + report::escape_html(options.command_line) + "</code>";
  html.raw(text + "</p>\n");
}

void reliability_section(report::HtmlReport& html, const evaluation::Calibration& c, const std::string& what) {
  // 240 x 240 plot area, 40 px margins: x = mean confidence of the bin, y = share right.
  constexpr double kSize = 240, kLeft = 44, kTop = 12;
  std::string svg = fmt::format(
      R"svg(<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" font-family="sans-serif" font-size="11">)svg",
      kLeft + kSize + 16, kTop + kSize + 40);
  svg += fmt::format(R"svg(<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#888"/>)svg", kLeft, kTop,
                     kSize, kSize);
  svg += fmt::format(R"svg(<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="#888" stroke-dasharray="4 3"/>)svg", kLeft,
                     kTop + kSize, kLeft + kSize, kTop);
  for (const auto& b : c.bins) {
    if (b.count == 0) continue;
    const double x = kLeft + b.lower * kSize, w = (b.upper - b.lower) * kSize, h = b.accuracy * kSize;
    svg += fmt::format(
        R"svg(<rect x="{:.1f}" y="{:.1f}" width="{:.1f}" height="{:.1f}" fill="#285adc" fill-opacity="0.7" stroke="#fff">)svg"
        R"svg(<title>confidence {:.1f}-{:.1f}: {} {}, mean confidence {:.3f}, right {:.3f}</title></rect>)svg",
        x, kTop + kSize - h, w, h, b.lower, b.upper, b.count, what, b.mean_confidence, b.accuracy);
    svg += fmt::format(R"svg(<circle cx="{:.1f}" cy="{:.1f}" r="2.5" fill="#dc1e1e"/>)svg",
                       kLeft + b.mean_confidence * kSize, kTop + kSize - b.accuracy * kSize);
  }
  for (int t = 0; t <= 4; ++t) {
    const double v = 0.25 * t;
    svg += fmt::format(R"svg(<text x="{:.1f}" y="{:.1f}" text-anchor="middle">{:.2g}</text>)svg", kLeft + v * kSize,
                       kTop + kSize + 14, v);
    svg += fmt::format(R"svg(<text x="{:.1f}" y="{:.1f}" text-anchor="end">{:.2g}</text>)svg", kLeft - 4,
                       kTop + kSize - v * kSize + 4, v);
  }
  svg += fmt::format(R"svg(<text x="{:.1f}" y="{:.1f}" text-anchor="middle">confidence</text>)svg", kLeft + kSize / 2,
                     kTop + kSize + 30);
  svg +=
      fmt::format(R"svg(<text transform="translate(11,{:.1f}) rotate(-90)" text-anchor="middle">share right</text>)svg",
                  kTop + kSize / 2);
  svg += "</svg>";
  html.raw(fmt::format(
      "<p class=\"note\">Reliability diagram: the {} binned by confidence; each bar is the share of its bin that is "
      "right against the truth, the red dot its mean confidence. A calibrated confidence sits on the dashed "
      "diagonal. Expected calibration error {:.3f} over {} {}.</p>\n",
      report::escape_html(what), c.ece, c.detections, report::escape_html(what)));
  html.raw("<div class=\"figure\">" + svg + "</div>\n");
  std::vector<std::vector<std::string>> rows;
  for (const auto& b : c.bins) {
    rows.push_back({fmt::format("{:.1f}-{:.1f}", b.lower, b.upper), std::to_string(b.count),
                    b.count ? fmt::format("{:.3f}", b.mean_confidence) : "",
                    b.count ? fmt::format("{:.3f}", b.accuracy) : ""});
  }
  html.begin_details("the bins");
  html.table({"confidence", what, "mean confidence", "share right"}, rows);
  html.end_details();
}

nlohmann::json pr_json(const std::vector<CurvePoints>& curves) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t k = 0; k < curves.size(); ++k) {
    nlohmann::json points = nlohmann::json::array();
    for (const auto& p : curves[k].points) points.push_back({p[0], p[1], p[2]});
    out.push_back(
        {{"label", curves[k].label}, {"primary", k == 0}, {"colour", curves[k].colour}, {"points", std::move(points)}});
  }
  return {{"curves", std::move(out)}};
}

nlohmann::json timings_json(std::vector<std::pair<std::string, double>>& rows, const ReportOptions& options,
                            std::chrono::steady_clock::time_point report_start) {
  const double own = std::chrono::duration<double>(std::chrono::steady_clock::now() - report_start).count();
  rows.emplace_back("report (thumbnails, page)", own);
  double sum = 0;
  for (const auto& r : rows) sum += r.second;
  double wall = sum;
  if (options.seconds_before) {
    wall = *options.seconds_before + own;
    if (wall - sum > 0.0005) rows.emplace_back("other (between stages)", wall - sum);
    wall = std::max(wall, sum);
  }
  nlohmann::json j = {{"wall", wall}, {"rows", nlohmann::json::array()}};
  for (const auto& [stage, seconds] : rows) j["rows"].push_back({stage, seconds});
  return j;
}

ReportResult finish_interactive(report::HtmlReport& html, const nlohmann::json& data) {
  ReportResult result;
  const auto d3 = report::read_d3_library();
  if (!d3) {
    result.interactive = false;
    result.warning = fmt::format(
        "{} not found (Debian package libjs-d3, installed by scripts/setup.sh): report.html is static, "
        "without its interactive views",
        report::d3_library_path().string());
    html.raw(
        "<p class=\"note\" id=\"static-note\">This report is static: the interactive views need D3 (Debian's "
        "libjs-d3), which was not found at " +
        report::escape_html(report::d3_library_path().string()) + " when the report was written.</p>\n");
    return result;
  }
  // Non-finite numbers have no JSON form: they are written as null.
  html.interactive(data.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), *d3);
  return result;
}

std::string matrix_view_markup(const std::string& help) {
  return "<p class=\"note\">" + report::escape_html(help) +
         "</p>\n<div class=\"controls\"><button id=\"matrix-zoom-in\" type=\"button\">zoom in</button>"
         "<button id=\"matrix-zoom-out\" type=\"button\">zoom out</button>"
         "<button id=\"matrix-zoom-reset\" type=\"button\">reset</button> "
         "<span class=\"readout\" id=\"matrix-readout\"></span></div>\n"
         "<div class=\"view\"><div id=\"matrix-view\"></div>"
         "<div class=\"panel\" id=\"pair-viewer\"><span class=\"note\">Hover over a marker to see its two images "
         "side by side; click to pin.</span></div></div>\n";
}

}  // namespace seqtopo::outputs::detail

namespace seqtopo::outputs {

ThumbnailCollector::ThumbnailCollector(const std::vector<std::size_t>& session_frames) {
  std::size_t end = 0;
  for (std::size_t frames : session_frames) sides_.emplace_back(end += frames, report_thumbnail_side(frames));
}

void ThumbnailCollector::add(std::size_t index, const RgbImage& image) {
  const auto session =
      std::upper_bound(sides_.begin(), sides_.end(), index, [](std::size_t i, const auto& s) { return i < s.first; });
  if (session == sides_.end()) return;  // past the sessions announced: the report decodes it
  std::string jpeg = plot::encode_jpeg(plot::shrink(image, session->second), 75);
  const std::lock_guard lock(mutex_);
  if (jpegs_.size() <= index) jpegs_.resize(index + 1);
  jpegs_[index] = std::move(jpeg);
}

}  // namespace seqtopo::outputs
