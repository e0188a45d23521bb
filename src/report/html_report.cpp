#include "seqtopo/report/html_report.hpp"

#include "seqtopo/report/interactive.hpp"

namespace seqtopo::report {

std::string escape_html(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string base64(const std::string& bytes) {
  static const char kTable[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t k = 0;
  for (; k + 2 < bytes.size(); k += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[k]) << 16) | (static_cast<unsigned char>(bytes[k + 1]) << 8) |
                       static_cast<unsigned char>(bytes[k + 2]);
    out += kTable[(v >> 18) & 63];
    out += kTable[(v >> 12) & 63];
    out += kTable[(v >> 6) & 63];
    out += kTable[v & 63];
  }
  if (k < bytes.size()) {
    unsigned v = static_cast<unsigned char>(bytes[k]) << 16;
    if (k + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[k + 1]) << 8;
    out += kTable[(v >> 18) & 63];
    out += kTable[(v >> 12) & 63];
    out += k + 1 < bytes.size() ? kTable[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

HtmlReport::HtmlReport(std::string title) : title_(std::move(title)) {}

void HtmlReport::heading(const std::string& text) { body_ += "<h2>" + escape_html(text) + "</h2>\n"; }

void HtmlReport::paragraph(const std::string& text) { body_ += "<p>" + escape_html(text) + "</p>\n"; }

void HtmlReport::table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  body_ += "<table>\n<tr>";
  for (const auto& h : header) body_ += "<th>" + escape_html(h) + "</th>";
  body_ += "</tr>\n";
  for (const auto& row : rows) {
    body_ += "<tr>";
    for (const auto& cell : row) body_ += "<td>" + escape_html(cell) + "</td>";
    body_ += "</tr>\n";
  }
  body_ += "</table>\n";
}

void HtmlReport::key_values(const std::vector<std::pair<std::string, std::string>>& rows) {
  body_ += "<table class=\"kv\">\n";
  for (const auto& [k, v] : rows) body_ += "<tr><th>" + escape_html(k) + "</th><td>" + escape_html(v) + "</td></tr>\n";
  body_ += "</table>\n";
}

void HtmlReport::png(const std::string& caption, const std::string& png_bytes, const std::string& file_name) {
  body_ += "<figure><img alt=\"" + escape_html(caption) + "\" src=\"data:image/png;base64," + base64(png_bytes) +
           "\"><figcaption>" + escape_html(caption) + " (<code>" + escape_html(file_name) +
           "</code>)</figcaption></figure>\n";
}

void HtmlReport::svg(const std::string& caption, const std::string& svg_text, const std::string& file_name) {
  body_ += "<figure><img alt=\"" + escape_html(caption) + "\" src=\"data:image/svg+xml;base64," + base64(svg_text) +
           "\"><figcaption>" + escape_html(caption) + " (<code>" + escape_html(file_name) +
           "</code>)</figcaption></figure>\n";
}

void HtmlReport::raw(const std::string& markup) { body_ += markup; }

void HtmlReport::begin_details(const std::string& summary) {
  body_ += "<details><summary>" + escape_html(summary) + "</summary>\n";
}

void HtmlReport::end_details() { body_ += "</details>\n"; }

void HtmlReport::interactive(const std::string& json, const std::string& d3_text) {
  scripts_ += "<script type=\"application/json\" id=\"seqtopo-data\">" + script_text(json) + "</script>\n";
  scripts_ += "<script>/* D3 3.5, Debian libjs-d3, inlined */\n" + script_text(d3_text) + "\n</script>\n";
  scripts_ += "<script>\n" + script_text(interactive_script()) + "\n</script>\n";
}

namespace {

// The page's style: the static tables and figures, and the interactive views (interactive.js).
constexpr const char* kStyle =
    "body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}"
    "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:3px 8px;text-align:left}"
    "th{background:#f3f3f3}figure{margin:1em 0}img{max-width:100%;border:1px solid #ddd}"
    "figcaption{color:#555;font-size:90%}details{margin:1em 0}summary{cursor:pointer;font-weight:bold}"
    ".view{display:flex;flex-wrap:wrap;gap:16px;align-items:flex-start}"
    ".panel{flex:1 1 300px;min-width:280px;border:1px solid #ddd;padding:8px;background:#fafafa;min-height:120px}"
    ".note{color:#555;font-size:90%}.readout{font-family:monospace;font-size:85%;color:#333;min-height:1.2em}"
    ".controls button{margin-right:4px}.pair-title{font-weight:bold;margin-bottom:6px}"
    ".thumb-row{display:flex;flex-wrap:wrap;gap:8px}.thumb-figure{margin:0}"
    "img.thumb{width:180px;max-width:100%;image-rendering:pixelated;border:1px solid #888}"
    ".thumb-row .thumb-row img.thumb,#place-viewer img.thumb{width:120px}"
    ".no-thumb{width:200px;height:90px;border:1px dashed #aaa;color:#666;font-size:85%;padding:4px}"
    "svg text{font-size:11px}.axis path,.axis line{fill:none;stroke:#222;shape-rendering:crispEdges}"
    ".axis-label{font-size:12px}.frame{fill:none;stroke:#222}"
    ".matrix-image{image-rendering:pixelated}"
    "path.alignment{fill:none;stroke-width:2px;vector-effect:non-scaling-stroke}"
    "path.alignment.kept{stroke:#ff1e1e}path.alignment.pruned{stroke:#286eff;stroke-dasharray:4 3}"
    "svg.localize path.alignment.reverse{stroke:#1ec83c}"
    "circle.pair{fill:#ffd000;stroke:#000;stroke-width:0.6px;vector-effect:non-scaling-stroke;cursor:pointer}"
    "circle.pair.active{fill:#00e5ff}circle.pair.pinned{fill:#ff00d0}"
    ".cell-cursor{fill:none;stroke:#00e5ff;stroke-width:1px}"
    "rect.error{fill:none;stroke-width:2px;vector-effect:non-scaling-stroke}rect.error.fp{stroke:#ff00ff}"
    "rect.error.miss{stroke:#ffc800}img.error-thumb{max-width:180px;max-height:140px}"
    "table.errors td{vertical-align:top}"
    "line.edge{stroke:#999;stroke-width:1.2px;vector-effect:non-scaling-stroke}"
    "circle.node{fill:#ddd;stroke:#444;stroke-width:0.8px;cursor:pointer;vector-effect:non-scaling-stroke}"
    "circle.node.revisited{fill:#377eb8}circle.node.run{fill:#9ecae1}circle.node.junction{fill:#e41a1c}"
    "circle.node.selected{stroke:#000;stroke-width:3px}"
    "path.curve{fill:none;stroke-width:2px}path.curve.primary{stroke-width:3px}"
    "path.curve.baseline{stroke-dasharray:7 4}line.curve{stroke-width:2px}line.curve.baseline{stroke-dasharray:5 3}"
    ".overlay{fill:none;pointer-events:all}rect.bin{fill:#4a7fb5}rect.bin.active{fill:#ff7f0e}"
    "rect.stage{stroke:#fff}.legend span{margin-right:10px;font-size:90%}"
    "table.alignments tr.alignment-row{cursor:pointer}table.alignments tr.alignment-row:hover{background:#eef}";

}  // namespace

std::string HtmlReport::html() const {
  return "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + escape_html(title_) +
         "</title>\n<style>" + kStyle + "</style></head>\n<body>\n<h1>" + escape_html(title_) + "</h1>\n" + body_ +
         scripts_ + "</body></html>\n";
}

}  // namespace seqtopo::report
