#include "seqtopo/formats/alignment_json.hpp"

#include <stdexcept>

namespace seqtopo::formats {

nlohmann::json to_json(const align::LocalAlignment& a) {
  nlohmann::json pairs = nlohmann::json::array();
  for (auto [i, j] : a.pairs) pairs.push_back({i, j});
  return {{"score", a.score},         {"direction", align::to_string(a.direction)},
          {"a_begin", a.a_begin},     {"a_end", a.a_end},
          {"b_begin", a.b_begin},     {"b_end", a.b_end},
          {"pairs", std::move(pairs)}};
}

nlohmann::json alignments_to_json(const std::vector<align::LocalAlignment>& alignments, const std::vector<bool>* kept) {
  if (kept && kept->size() != alignments.size()) throw std::invalid_argument("one kept flag per alignment needed");
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t k = 0; k < alignments.size(); ++k) {
    nlohmann::json a = to_json(alignments[k]);
    if (kept) a["kept"] = static_cast<bool>((*kept)[k]);
    list.push_back(std::move(a));
  }
  return {{"alignments", std::move(list)}};
}

std::vector<align::LocalAlignment> alignments_from_json(const nlohmann::json& document) {
  std::vector<align::LocalAlignment> out;
  for (const auto& a : document.at("alignments")) {
    align::LocalAlignment x;
    x.score = a.at("score").get<align::Score>();
    x.direction =
        a.at("direction").get<std::string>() == "reverse" ? align::Direction::reverse : align::Direction::forward;
    x.a_begin = a.at("a_begin").get<std::size_t>();
    x.a_end = a.at("a_end").get<std::size_t>();
    x.b_begin = a.at("b_begin").get<std::size_t>();
    x.b_end = a.at("b_end").get<std::size_t>();
    for (const auto& p : a.at("pairs")) x.pairs.emplace_back(p.at(0).get<std::size_t>(), p.at(1).get<std::size_t>());
    out.push_back(std::move(x));
  }
  return out;
}

}  // namespace seqtopo::formats
