#include "seqtopo/formats/online_events.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <string_view>

#include "seqtopo/formats/json_number.hpp"

namespace seqtopo::formats {
namespace {

using mapping::OnlineEvent;
using mapping::OnlineEventKind;
using Json = nlohmann::ordered_json;

}  // namespace

std::string online_event_json(const OnlineEvent& e) {
  Json j = {{"frame", e.frame}, {"event", std::string(mapping::to_string(e.kind))}};
  const auto direction = [&] { j["direction"] = std::string(align::to_string(e.direction)); };
  // The E-value of the score in the frames so far; null before the statistics could be fitted.
  const auto e_value = [&] { j["e_value"] = e.e_value ? Json(std::stod(fmt::format("{:.3g}", *e.e_value))) : Json(); };
  switch (e.kind) {
    case OnlineEventKind::loop_closure:
      j["i"] = e.i;
      j["j"] = e.j;
      direction();
      j["confidence"] = json_number(e.confidence);
      j["score"] = json_number(e.score);
      e_value();
      j["revisit"] = e.revisit;
      break;
    case OnlineEventKind::revisit_begin:
      j["revisit"] = e.revisit;
      direction();
      j["i"] = e.i;
      j["j"] = e.j;
      j["score"] = json_number(e.score);
      e_value();
      j["delay"] = e.frame - e.first;
      if (e.candidate) j["candidate"] = *e.candidate;
      break;
    case OnlineEventKind::revisit_candidate:
      j["candidate"] = *e.candidate;
      direction();
      j["i"] = e.i;
      j["j"] = e.j;
      j["start"] = {e.first, e.last};
      j["score"] = json_number(e.score);
      e_value();
      j["delay"] = e.frame - e.first;
      break;
    case OnlineEventKind::revisit_end:
      j["revisit"] = e.revisit;
      direction();
      j["i"] = e.i;
      j["j"] = e.j;
      j["first"] = e.first;
      j["last"] = e.last;
      j["frames"] = e.frames;
      j["score"] = json_number(e.score);
      e_value();
      break;
    case OnlineEventKind::junction:
      j["i"] = e.i;
      j["j"] = e.j;
      j["joining"] = e.joining;
      j["revisit"] = e.revisit;
      direction();
      break;
    case OnlineEventKind::place_merge:
      j["i"] = e.i;
      j["j"] = e.j;
      j["places"] = {e.first, e.last};
      j["revisit"] = e.revisit;
      break;
    case OnlineEventKind::correction: {
      if (e.candidate) {
        j["candidate"] = *e.candidate;
      } else {
        j["revisit"] = e.revisit;
      }
      direction();
      j["reason"] = e.reason;
      Json withdrawn = Json::array();
      for (const auto& [i, k] : e.withdrawn) withdrawn.push_back({i, k});
      j["withdrawn"] = std::move(withdrawn);
      break;
    }
    case OnlineEventKind::session_break:
      j["i"] = e.i;
      j["j"] = e.j;
      j["gap"] = e.gap;
      j["median_interval"] = e.median_interval;
      break;
  }
  return j.dump();
}

std::string online_event_summary(const OnlineEvent& e) {
  const std::string_view d = align::to_string(e.direction);
  switch (e.kind) {
    case OnlineEventKind::loop_closure:
      return fmt::format("frame {}: loop closure {} ~ {} ({}, confidence {:.2f})", e.frame, e.i, e.j, d, e.confidence);
    case OnlineEventKind::revisit_begin:
      return fmt::format("frame {}: revisit {} begins at {} ~ {} ({}, {} frames late{})", e.frame, e.revisit, e.i, e.j,
                         d, e.frame - e.first,
                         e.candidate ? fmt::format(", candidate {} confirmed", *e.candidate) : std::string());
    case OnlineEventKind::revisit_candidate:
      return fmt::format("frame {}: revisit candidate {} at {} ~ {} ({}, E-value {}, from {} ~ {})", e.frame,
                         *e.candidate, e.i, e.j, d, e.e_value ? fmt::format("{:.3g}", *e.e_value) : "?", e.first,
                         e.last);
    case OnlineEventKind::revisit_end:
      return fmt::format("frame {}: revisit {} ended at {} ~ {} ({}, frames {}-{})", e.frame, e.revisit, e.i, e.j, d,
                         e.first, e.last);
    case OnlineEventKind::junction:
      return fmt::format("frame {}: junction at frame {} (frame {} {} the old path)", e.frame, e.j, e.i,
                         e.joining ? "joins" : "leaves");
    case OnlineEventKind::place_merge:
      return fmt::format("frame {}: places {} and {} merged ({} ~ {})", e.frame, e.first, e.last, e.i, e.j);
    case OnlineEventKind::correction:
      if (e.candidate) return fmt::format("frame {}: correction, {}", e.frame, e.reason);
      return fmt::format("frame {}: correction, {} loop closure(s) of revisit {} withdrawn: {}", e.frame,
                         e.withdrawn.size(), e.revisit, e.reason);
    case OnlineEventKind::session_break:
      return fmt::format(
          "frame {}: session break before frame {} ({:.3g} s without a frame, the recording's median "
          "interval {:.3g} s, and the frames either side unlike neighbours)",
          e.frame, e.i, e.gap, e.median_interval);
  }
  return {};
}

}  // namespace seqtopo::formats
