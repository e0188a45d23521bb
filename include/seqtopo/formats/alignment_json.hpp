#pragma once
// alignments.json (INTERFACE.md): {"alignments": [{"score", "direction", "a_begin", "a_end", "b_begin",
// "b_end", "pairs", "kept"?}]}
#include <nlohmann/json.hpp>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"

namespace seqtopo::formats {

nlohmann::json to_json(const align::LocalAlignment& alignment);
// `kept`, when given, has one flag per alignment (the pruning verdict of the map pipeline).
nlohmann::json alignments_to_json(const std::vector<align::LocalAlignment>& alignments,
                                  const std::vector<bool>* kept = nullptr);
std::vector<align::LocalAlignment> alignments_from_json(const nlohmann::json& document);

}  // namespace seqtopo::formats
