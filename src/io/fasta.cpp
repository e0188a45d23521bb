#include "seqtopo/io/fasta.hpp"

#include <cctype>
#include <sstream>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/text_file.hpp"

namespace seqtopo::io {

std::vector<FastaRecord> read_fasta(const std::filesystem::path& path) {
  std::istringstream in(read_text_file(path, "FASTA file"));
  std::vector<FastaRecord> records;
  std::string line;
  std::size_t line_no = 0;
  auto check_last = [&] {
    if (!records.empty() && records.back().sequence.empty()) {
      throw InputError(path.string(), "record '" + records.back().name + "' has an empty sequence");
    }
  };
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty() && line.front() == '>') {
      check_last();
      records.push_back({line.substr(1), {}});
      continue;
    }
    std::string residues;
    for (char c : line) {
      if (!std::isspace(static_cast<unsigned char>(c))) residues.push_back(c);
    }
    if (residues.empty()) continue;
    if (records.empty())
      throw InputError(path.string() + ":" + std::to_string(line_no), "sequence before the first '>' header");
    records.back().sequence += residues;
  }
  check_last();
  if (records.empty()) throw InputError(path.string(), "no FASTA record");
  return records;
}

}  // namespace seqtopo::io
