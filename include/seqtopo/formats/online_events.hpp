#pragma once
// The online mapper's events as `seqtopo map --online` writes them (INTERFACE.md, docs/online.md): one JSON object
// per line of events.jsonl, and one human-readable line for the terminal.
#include <string>

#include "seqtopo/mapping/online_mapper.hpp"

namespace seqtopo::formats {

// {"frame", "event", ...the fields of its kind}, on one line (no newline). Scores and confidences are the floats'
// shortest decimals; an E-value has three significant digits, null before the statistics could be fitted.
std::string online_event_json(const mapping::OnlineEvent& event);
// One line (no newline), e.g. "frame 57: loop closure 57 ~ 12 (forward, confidence 0.93)".
std::string online_event_summary(const mapping::OnlineEvent& event);

}  // namespace seqtopo::formats
