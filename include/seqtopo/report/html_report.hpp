#pragma once
// A self-contained HTML report: every figure is inlined (data: URIs or inline SVG), so the page opens
// with no network access and can be mailed or archived as one file.
#include <string>
#include <utility>
#include <vector>

namespace seqtopo::report {

class HtmlReport {
 public:
  explicit HtmlReport(std::string title);
  void heading(const std::string& text);
  void paragraph(const std::string& text);  // text is escaped
  void table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows);
  void key_values(const std::vector<std::pair<std::string, std::string>>& rows);
  void png(const std::string& caption, const std::string& png_bytes, const std::string& file_name);
  void svg(const std::string& caption, const std::string& svg_text, const std::string& file_name);
  // Markup written as it is (the caller's own, trusted: element skeletons of the interactive views).
  void raw(const std::string& markup);
  // <details> around what is added until end_details(): a section folded by default.
  void begin_details(const std::string& summary);
  void end_details();
  // The interactive page (interactive.hpp): the JSON data block, D3 and the page's script, at the end of the
  // body. `json` is the data block's text.
  void interactive(const std::string& json, const std::string& d3_text);
  std::string html() const;

 private:
  std::string title_;
  std::string body_;
  std::string scripts_;
};

std::string escape_html(const std::string& text);
std::string base64(const std::string& bytes);

}  // namespace seqtopo::report
