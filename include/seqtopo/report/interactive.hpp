#pragma once
// The interactive part of a report: a JSON data block the page reads, the page's own script
// (src/report/interactive.js, compiled in) and the charting library it runs on, D3 3.5 from Debian's libjs-d3,
// read from its installed file when the report is written and inlined, so that the page needs no network.
//
// The data block is one JSON object (docs/INTERFACE.md, "report.html"): the sequences with their thumbnails,
// the matrix image with its range, the alignments, the pairs (loop closures or matches) with their fields, the
// topology, the PR curves, the histogram of the pairs' confidence, parameters and timings. The page shows
// whatever per-pair fields the block lists (`pairs.fields`), so a new field is one more entry there.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace seqtopo::report {

// Where D3 is read from: $SEQTOPO_D3_JS when set (tests point it at a missing file), else
// /usr/share/javascript/d3/d3.min.js (Debian's libjs-d3).
std::filesystem::path d3_library_path();
// The library's text, or nullopt when the file is missing or unreadable.
std::optional<std::string> read_d3_library();
// The page's script.
std::string_view interactive_script();
// Text made safe to put inside <script>...</script> (no "</" that could end it, no "<!--").
std::string script_text(std::string_view text);

}  // namespace seqtopo::report
