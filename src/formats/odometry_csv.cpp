#include "seqtopo/formats/odometry_csv.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>
#include <string>
#include <string_view>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/text_file.hpp"
#include "seqtopo/io/csv.hpp"
#include "trim.hpp"

namespace seqtopo::formats {
namespace {

using detail::trim;

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> fields;
  for (;;) {
    const auto comma = line.find(',');
    fields.push_back(trim(line.substr(0, comma)));
    if (comma == std::string_view::npos) return fields;
    line.remove_prefix(comma + 1);
  }
}

// Every row of a pose file, checked: fields.size() numbers per row, the first one the row's index.
struct PoseTable {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;  // without the index
  std::vector<std::size_t> lines;         // the line number of each row
};

PoseTable read_table(const std::filesystem::path& path, const std::vector<std::vector<std::string>>& headers) {
  std::istringstream in(read_text_file(path, "pose file"));
  io::skip_byte_order_mark(in);
  auto where = [&](std::size_t line_no) { return path.string() + ":" + std::to_string(line_no); };
  auto expected = [&] {
    std::string text;
    for (const auto& h : headers) {
      std::string joined;
      for (const auto& name : h) joined += (joined.empty() ? "" : ",") + name;
      text += (text.empty() ? "`" : " or `") + joined + "`";
    }
    return text;
  };

  PoseTable table;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (trim(line).empty()) continue;
    const auto fields = split(line);
    if (table.header.empty()) {
      for (const auto& h : headers) {
        if (h.size() == fields.size() && std::equal(h.begin(), h.end(), fields.begin())) table.header = h;
      }
      if (table.header.empty()) throw InputError(where(line_no), "header must be " + expected());
      continue;
    }
    if (fields.size() != table.header.size()) {
      throw InputError(where(line_no), "expected " + std::to_string(table.header.size()) +
                                           " comma-separated fields, found " + std::to_string(fields.size()));
    }
    std::vector<double> values;
    for (std::size_t f = 0; f < fields.size(); ++f) {
      double v = 0;
      std::string_view text = fields[f];
      if (text.size() > 1 && text.front() == '+') text.remove_prefix(1);  // from_chars takes no '+'
      const char* end = text.data() + text.size();
      const auto [ptr, ec] = std::from_chars(text.data(), end, v);
      if (text.empty() || ec != std::errc() || ptr != end) {
        throw InputError(where(line_no),
                         "field '" + table.header[f] + "' is not a number: '" + std::string(fields[f]) + "'");
      }
      if (!std::isfinite(v)) throw InputError(where(line_no), "field '" + table.header[f] + "' is not finite");
      values.push_back(v);
    }
    const auto expected_index = static_cast<double>(table.rows.size());
    if (values[0] != expected_index) {
      throw InputError(where(line_no), "index " + std::string(fields[0]) + " out of order: expected " +
                                           std::to_string(table.rows.size()) + " (rows are images 0..N-1 in order)");
    }
    values.erase(values.begin());
    table.rows.push_back(std::move(values));
    table.lines.push_back(line_no);
  }
  if (table.header.empty()) throw InputError(path.string(), "empty file; header must be " + expected());
  if (table.rows.empty()) throw InputError(path.string(), "no rows after the header");
  return table;
}

}  // namespace

std::vector<Pose2> read_odometry_csv(const std::filesystem::path& path) {
  const PoseTable table = read_table(path, {{"index", "x", "y", "theta"}, {"index", "dx", "dy", "dtheta"}});
  std::vector<Pose2> poses;
  poses.reserve(table.rows.size());
  const bool increments = table.header[1] == "dx";
  Pose2 pose;  // the origin
  for (std::size_t k = 0; k < table.rows.size(); ++k) {
    const auto& r = table.rows[k];
    pose = increments ? compose(pose, {r[0], r[1], r[2]}) : Pose2{r[0], r[1], wrap_angle(r[2])};
    // Finite increments can still sum past the largest double (1e308 + 1e308).
    if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.theta)) {
      throw InputError(path.string() + ":" + std::to_string(table.lines[k]),
                       "the integrated position is not finite (the increments overflow)");
    }
    poses.push_back(pose);
  }
  return poses;
}

std::vector<Pose2> read_poses_csv(const std::filesystem::path& path) {
  const PoseTable table = read_table(path, {{"index", "x", "y"}, {"index", "x", "y", "theta"}});
  std::vector<Pose2> poses;
  poses.reserve(table.rows.size());
  for (const auto& r : table.rows) poses.push_back({r[0], r[1], r.size() > 2 ? wrap_angle(r[2]) : 0.0});
  return poses;
}

}  // namespace seqtopo::formats
