// Ranking with ties and the paper's exact / correct / wrong scoring.
#include <gtest/gtest.h>

#include "seqtopo/strings/localization.hpp"
#include "seqtopo/strings/strings_file.hpp"

namespace seqtopo::strings {
namespace {

TEST(Localization, RanksWithTiesKept) {
  const std::vector<std::string> db = {"vAvB", "vAvC", "vAvB", "DDDD"};
  MatchConfig config;
  config.k = 2;
  const auto matches = match_all(db, {"vAvB"}, config);
  ASSERT_EQ(matches.size(), 1U);
  const auto& r = matches[0].ranked;
  ASSERT_EQ(r.size(), 3U);  // "DDDD" needs 4 differences: no candidate
  EXPECT_EQ(r[0].db_index, 0U);
  EXPECT_EQ(r[1].db_index, 2U);
  EXPECT_EQ(r[0].rank, 1U);
  EXPECT_EQ(r[1].rank, 1U);
  EXPECT_EQ(r[2].rank, 3U);
  EXPECT_EQ(matches[0].best(), (std::vector<std::size_t>{0, 2}));
}

TEST(Localization, ScoresOfTheThreeAlgorithms) {
  MatchConfig config;
  config.algorithm = Algorithm::B;
  config.k = 1;
  EXPECT_EQ(score_pair("vAB", "CCvABvAAB", config).score, 0.0);
  EXPECT_FALSE(score_pair("vvvv", "ABAB", config).matched);
  config.algorithm = Algorithm::C;
  EXPECT_EQ(score_pair("vABvC", "AvBCv", config).score, 4.0);  // 5 + 5 - 2 * 3
  config.cyclic = true;
  EXPECT_EQ(score_pair("BvCvA", "vAvBvC", config).score, 1.0);  // a rotation contains it
  config.algorithm = Algorithm::A;
  config.k = kNoLimit;
  EXPECT_EQ(score_pair("vBvCvA", "vAvBvC", config).score, 0.0);
  EXPECT_EQ(score_pair("vBvCvA", "vAvBvC", config).rotation, 2U);
  EXPECT_THROW(parse_algorithm("D"), std::invalid_argument);
}

TEST(Localization, SequenceOfConsecutiveQueries) {
  // Two map points look the same ("CCCC"); the queries before the last one tell them apart.
  const std::vector<std::string> db = {"AAAA", "BBBB", "CCCC", "XXXX", "YYYY", "CCCC"};
  const std::vector<std::string> queries = {"AAAA", "BBBB", "CCCC"};
  MatchConfig config;
  EXPECT_EQ(match_all(db, queries, config)[2].best(), (std::vector<std::size_t>{2, 5}));
  const auto three = match_all_windowed(db, queries, config, 3);
  EXPECT_EQ(three[2].best(), (std::vector<std::size_t>{2}));
  EXPECT_EQ(three[2].ranked[0].score, 0.0);
  for (const auto& c : three[2].ranked) {
    if (c.db_index == 5) {
      EXPECT_DOUBLE_EQ(c.score, 8.0 / 3.0);  // the chain 1 -> 3 -> 5
    }
  }
  // Chains never go backwards: after "CCCC", "DDDD", the query "AAAA" is placed after them.
  const auto back = match_all_windowed({"AAAA", "BBBB", "CCCC", "DDDD"}, {"CCCC", "DDDD", "AAAA"}, config, 3);
  EXPECT_EQ(back[2].best(), (std::vector<std::size_t>{3}));
  EXPECT_DOUBLE_EQ(back[2].ranked[0].score, 4.0 / 3.0);
  EXPECT_THROW(match_all_windowed(db, queries, config, 0), std::invalid_argument);
}

QueryMatches with_best(std::vector<std::size_t> best, std::size_t others_from) {
  QueryMatches m;
  for (std::size_t d : best) m.ranked.push_back({d, 0.0, 1, 0});
  m.ranked.push_back({others_from, 1.0, best.size() + 1, 0});
  return m;
}

TEST(Localization, PaperScoring) {
  // Map points 0..3 at x = 0, 1, 2, 3; test points near 0, 1, 2, 3 and 0.
  GroundTruth truth;
  truth.db_positions = {Point2{0, 0}, Point2{1, 0}, Point2{2, 0}, Point2{3, 0}};
  truth.query_positions = {Point2{0.1, 0}, Point2{0.9, 0}, Point2{2.2, 0}, Point2{3, 0.4}, Point2{0.2, 0}};
  // Adjacent: the closest map point and its neighbours.
  truth.adjacent = {{true, true, false, false},
                    {true, true, true, false},
                    {false, true, true, true},
                    {false, false, true, true},
                    {true, true, false, false}};
  const std::vector<QueryMatches> matches = {
      with_best({0}, 3),     // topologically exact, geometrically exact
      with_best({0}, 3),     // topologically exact, geometrically wrong (closest is 1)
      with_best({1, 2}, 0),  // topologically correct (not exact), geometrically correct (not exact)
      with_best({0}, 1),     // topologically wrong: left out of the geometric figures
      with_best({1, 3}, 2),  // topologically correct, geometrically wrong
  };
  const auto metrics = score_localization(matches, truth);
  ASSERT_TRUE(metrics.topological);
  EXPECT_EQ(metrics.topological->total, 5U);
  EXPECT_EQ(metrics.topological->exact, 2U);
  EXPECT_EQ(metrics.topological->correct, 4U);
  EXPECT_EQ(metrics.topological->wrong, 1U);
  ASSERT_TRUE(metrics.geometric);
  EXPECT_EQ(metrics.geometric->total, 4U);
  EXPECT_EQ(metrics.geometric->exact, 1U);
  EXPECT_EQ(metrics.geometric->correct, 2U);
  EXPECT_EQ(metrics.geometric->wrong, 2U);
  EXPECT_DOUBLE_EQ(metrics.geometric->percent(2), 50.0);
}

TEST(Localization, NoCandidateIsWrong) {
  GroundTruth truth;
  truth.adjacent = {{true}};
  const auto metrics = score_localization({QueryMatches{}}, truth);
  EXPECT_EQ(metrics.topological->wrong, 1U);
  EXPECT_FALSE(score_localization({QueryMatches{}}, GroundTruth{}).topological.has_value());
}

TEST(StringsFile, ParsesAndRoundTrips) {
  const std::string text = "# map\nm0\tvAvB\t1.5\t-2\troom1\n\nm1\tvvC\nm2\t\n";
  const auto records = parse_strings_tsv(text);
  ASSERT_EQ(records.size(), 3U);
  EXPECT_EQ(records[0].id, "m0");
  EXPECT_EQ(records[0].symbols, "vAvB");
  EXPECT_EQ(*records[0].x, 1.5);
  EXPECT_EQ(*records[0].y, -2.0);
  EXPECT_EQ(*records[0].place, "room1");
  EXPECT_FALSE(records[1].x.has_value());
  EXPECT_EQ(records[2].symbols, "");
  EXPECT_EQ(parse_strings_tsv(format_strings_tsv(records)).size(), 3U);
}

// Found by the fuzz harness: the largest double was written with 10 digits (above it, not a number), and a place
// ending in '\r' came back without it.
TEST(StringsFile, CoordinatesRoundTripToTheBitAndControlCharactersAreRefused) {
  std::vector<StringRecord> records(2);
  records[0].id = "a";
  records[0].x = 1.7976931348623157e308;
  records[0].y = 0.1 + 0.2;
  records[1].id = "b";
  records[1].x = -4.9e-324;
  records[1].y = 1.5;
  records[1].place = "p";
  const auto again = parse_strings_tsv(format_strings_tsv(records));
  ASSERT_EQ(again.size(), 2U);
  EXPECT_EQ(again[0].x, records[0].x);
  EXPECT_EQ(again[0].y, records[0].y);
  EXPECT_EQ(again[1].x, records[1].x);
  EXPECT_NE(format_strings_tsv(records).find("\t1.5\t"), std::string::npos) << "short numbers stay short";
  EXPECT_THROW(parse_strings_tsv("a\tv\t1\t2\tp\r\r\n"), StringsFileError);
  EXPECT_THROW(parse_strings_tsv("a\x01\tv\n"), StringsFileError);
}

TEST(StringsFile, MalformedLinesNameTheLine) {
  auto line_of = [](const std::string& text) {
    try {
      parse_strings_tsv(text);
    } catch (const StringsFileError& e) {
      return e.line();
    }
    return std::size_t{0};
  };
  EXPECT_EQ(line_of("a\tvA\nb\tvB\t1\n"), 2U);    // x without y
  EXPECT_EQ(line_of("a\tvA\n# c\na\tvB\n"), 3U);  // repeated id
  EXPECT_EQ(line_of("a\tvA\tone\t2\n"), 1U);      // not a number
  EXPECT_EQ(line_of("a\n"), 1U);                  // no string
  EXPECT_EQ(line_of("\tvA\n"), 1U);               // empty id
  EXPECT_EQ(line_of("a\tvA\t1\t2\t\n"), 1U);      // empty place
  EXPECT_EQ(line_of("a\tvA\t1\t2\tp\n"), 0U);
}

}  // namespace
}  // namespace seqtopo::strings
