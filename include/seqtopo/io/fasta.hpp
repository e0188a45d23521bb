#pragma once
// FASTA sequences: '>' header lines, sequence lines concatenated with white space removed.
#include <filesystem>
#include <string>
#include <vector>

namespace seqtopo::io {

struct FastaRecord {
  std::string name;
  std::string sequence;
};

// Throws InputError (naming the file, and the line where it applies) on a missing file, text before
// the first header, a record with an empty sequence, or a file with no record.
std::vector<FastaRecord> read_fasta(const std::filesystem::path& path);

}  // namespace seqtopo::io
