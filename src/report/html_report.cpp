#include "seqtopo/report/html_report.hpp"

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

std::string HtmlReport::html() const {
  return "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + escape_html(title_) +
         "</title>\n<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}"
         "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:3px 8px;text-align:left}"
         "th{background:#f3f3f3}figure{margin:1em 0}img{max-width:100%;border:1px solid #ddd}"
         "figcaption{color:#555;font-size:90%}</style></head>\n<body>\n<h1>" +
         escape_html(title_) + "</h1>\n" + body_ + "</body></html>\n";
}

}  // namespace seqtopo::report
