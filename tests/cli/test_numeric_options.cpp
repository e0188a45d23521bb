// Every numeric option of every command (issue #18, finding 1), found by reading the commands' --help: NaN,
// infinities, negatives, numbers beyond the type, trailing garbage and the values just outside the range the
// option's error message states are refused while the command line is parsed (exit 2, one line naming the
// option, nothing created), and the values just inside are accepted. A new numeric option is covered without
// touching this file; one that legitimately takes a negative number is listed below with the reason.
//
// Each run ends with an unknown sentinel argument: a value the parser accepts ends in "not expected" (or a
// missing required option), so no command does any work here.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/cli_run.hpp"
#include "common/temp_dir.hpp"

namespace {
namespace fs = std::filesystem;
using seqtopo::test_support::CommandResult;
using seqtopo::test_support::run_command;

struct NumericOption {
  std::string binary;               // path of the executable
  std::string command;              // "map", "bench scale", "sparse" (seqtopo-mpi)
  std::vector<std::string> names;   // "--contrast-offset", "--offset"
  std::string type;                 // FLOAT, INT or UINT
  std::optional<std::string> word;  // "auto" of FLOAT|auto
  bool list = false;                // UINT ... (comma-separated)
  std::string label() const { return command + " " + names.front(); }
};

// Options that take a negative number on purpose, with a negative value they accept.
const std::map<std::string, std::pair<std::string, std::string>> kNegativeAllowed = {
    {"align --match", {"-1", "a score: any finite number"}},
    {"align --mismatch", {"-1", "a score, negative by default"}},
    {"bench scale --background", {"-1", "the score of non-candidate pairs must be < 0"}},
    {"localize --threshold", {"-1", "online: minimum confidence, any finite number"}},
    {"localize --contrast-offset", {"-1", "subtracted after enhancement, either sign"}},
    {"map --contrast-offset", {"-1", "subtracted after enhancement, either sign"}},
    {"match-strings --coincidence-cost", {"-1", "a reward for equal symbols (the paper's tables)"}},
    {"simulate --heading-drift", {"-0.01", "drift to either side [rad/m]"}},
    {"simulate --scale-error", {"-0.01", "odometry reading short (> -1)"}},
    {"sparse --background", {"-1", "the score of non-candidate pairs must be < 0"}},
    {"sparse --contrast-offset", {"-1", "subtracted after enhancement, either sign"}},
};

const std::string kSentinel = " --seqtopo-test-sentinel";

std::string quote(const std::string& text) { return "'" + text + "'"; }

CommandResult run(const NumericOption& o, const std::string& name, const std::string& value, const fs::path& out) {
  return run_command("exec " + o.binary + " " + o.command + " " + name + " " + quote(value) + " --out " + out.string() +
                     kSentinel);
}

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

// `seqtopo ... --help`: the subcommands ("Subcommands:" section) and the numeric options ("Options:").
std::vector<std::string> subcommands(const std::string& help) {
  std::vector<std::string> names;
  std::istringstream lines(help);
  bool in_section = false;
  for (std::string line; std::getline(lines, line);) {
    if (line == "Subcommands:") {
      in_section = true;
    } else if (line.empty() || line[0] != ' ') {
      in_section = false;
    } else if (in_section) {
      std::istringstream words(line);
      std::string name;
      words >> name;
      names.push_back(name);
    }
  }
  return names;
}

std::vector<NumericOption> numeric_options(const std::string& binary, const std::string& command,
                                           const std::string& help) {
  static const std::regex option(
      R"(^\s+(?:-\w,)?(--[a-z][-a-z0-9]*(?:,--[a-z][-a-z0-9]*)*)\s+(FLOAT|INT|UINT)(\|[a-z]+)?(?::\S+)?(?:=\S*)?( \.\.\.)?(\s|$).*)");
  std::vector<NumericOption> found;
  std::istringstream lines(help);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (!std::regex_match(line, m, option)) continue;
    NumericOption o{binary, command, {}, m[2], std::nullopt, m[4].matched};
    std::stringstream names(m[1].str());
    for (std::string name; std::getline(names, name, ',');) o.names.push_back(name);
    if (m[3].matched) o.word = m[3].str().substr(1);
    found.push_back(o);
  }
  return found;
}

std::vector<NumericOption> every_numeric_option() {
  std::vector<NumericOption> all;
  const std::string seqtopo = SEQTOPO_CLI;
  std::vector<std::string> commands;
  for (const auto& c : subcommands(run_command("exec " + seqtopo + " --help").out)) {
    const std::string help = run_command("exec " + seqtopo + " " + c + " --help").out;
    const auto nested = subcommands(help);
    if (nested.empty()) {
      commands.push_back(c);
    } else {
      for (const auto& n : nested) commands.push_back(c + " " + n);
    }
  }
  for (const auto& c : commands) {
    const auto options = numeric_options(seqtopo, c, run_command("exec " + seqtopo + " " + c + " --help").out);
    all.insert(all.end(), options.begin(), options.end());
  }
#ifdef SEQTOPO_MPI_CLI
  const std::string mpi =
      std::string("env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ") + SEQTOPO_MPI_CLI;
  const auto options = numeric_options(mpi, "sparse", run_command("exec " + mpi + " sparse --help").out);
  all.insert(all.end(), options.begin(), options.end());
#endif
  return all;
}

// The range an error message states: "expected an integer in [1, 8]", "a finite number > 0", ...
struct StatedRange {
  bool integer = false;
  std::optional<double> min, max;
  bool min_exclusive = false, max_exclusive = false;
};

std::optional<StatedRange> stated_range(const std::string& message) {
  static const std::regex in(R"(expected (an integer|a finite number) in ([\[(])([-0-9.e+]+), ([-0-9.e+]+)([\])]))");
  static const std::regex bound(R"(expected (an integer|a finite number) (>=|>|<=|<) ([-0-9.e+]+))");
  static const std::regex bare(R"(expected (an integer|a finite number)(,| or))");
  std::smatch m;
  StatedRange r;
  if (std::regex_search(message, m, in)) {
    r.integer = m[1] == "an integer";
    r.min = std::stod(m[3]);
    r.max = std::stod(m[4]);
    r.min_exclusive = m[2] == "(";
    r.max_exclusive = m[5] == ")";
    return r;
  }
  if (std::regex_search(message, m, bound)) {
    r.integer = m[1] == "an integer";
    const double v = std::stod(m[3]);
    if (m[2].str()[0] == '>') {
      r.min = v;
      r.min_exclusive = m[2] == ">";
    } else {
      r.max = v;
      r.max_exclusive = m[2] == "<";
    }
    return r;
  }
  if (std::regex_search(message, m, bare)) {
    r.integer = m[1] == "an integer";
    return r;
  }
  return std::nullopt;
}

std::string number_text(double v, bool integer) {
  std::ostringstream s;
  if (integer) {
    s << static_cast<long long>(v);
  } else {
    s.precision(17);
    s << v;
  }
  return s.str();
}

// One run of a command with one option value, and what the parser must do with it.
struct Case {
  const NumericOption* option = nullptr;
  std::string value;
  bool refused = true;
  CommandResult result{};
};

Case make_case(const NumericOption& o, std::string value, bool refused = true) {
  Case c;
  c.option = &o;
  c.value = std::move(value);
  c.refused = refused;
  return c;
}

// The sanitizer pass runs each option once, with the k-th of its cases for the k-th option, so every kind of
// value still meets the parser there; the Release pass runs them all. (An instrumented start of the binary
// takes about a second, and the parsing code is one function for every option.)
[[maybe_unused]] std::vector<Case> one_case_per_option(std::vector<Case> cases) {
  std::map<const NumericOption*, std::vector<Case>> by_option;
  std::vector<const NumericOption*> order;
  for (auto& c : cases) {
    auto& list = by_option[c.option];
    if (list.empty()) order.push_back(c.option);
    list.push_back(std::move(c));
  }
  std::vector<Case> kept;
  for (std::size_t k = 0; k < order.size(); ++k) {
    auto& list = by_option[order[k]];
    kept.push_back(std::move(list[k % list.size()]));
  }
  return kept;
}

// Runs every case, a few processes at a time (each start of the binary loads its libraries: ~0.1 s).
void run_all(std::vector<Case>& cases, const fs::path& dir) {
  std::atomic<std::size_t> next{0};
  const unsigned workers = std::max(4U, 3 * std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned w = 0; w < workers; ++w) {
    pool.emplace_back([&, w] {
      for (std::size_t k = next++; k < cases.size(); k = next++) {
        Case& c = cases[k];
        const auto& name = c.refused ? c.option->names.back() : c.option->names.front();
        c.result = run(*c.option, name, c.value, dir / ("never-" + std::to_string(w)));
      }
    });
  }
  for (auto& t : pool) t.join();
}

// Refused while parsing: exit 2 (a bad command line), one line naming the option (or one of its names), the
// value quoted. Accepted: the error (there is one, the sentinel) is about something else.
void check(const Case& c) {
  const NumericOption& o = *c.option;
  const CommandResult& r = c.result;
  SCOPED_TRACE(o.label() + " " + quote(c.value) + (c.refused ? " must be refused" : " must be accepted"));
  const std::string line = first_line(r.err);
  const bool names_option = std::any_of(o.names.begin(), o.names.end(), [&](const std::string& n) {
    return line.rfind("seqtopo: error: " + n + ":", 0) == 0 || line.rfind("seqtopo-mpi: error: " + n + ":", 0) == 0;
  });
  EXPECT_NE(r.status, -1) << "crashed";
  if (c.refused) {
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_TRUE(names_option) << line;
    EXPECT_NE(line.find("'" + c.value + "'"), std::string::npos) << "the value is quoted: " << line;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  } else {
    EXPECT_FALSE(names_option) << line;
  }
}

class NumericOptions : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { options_ = new std::vector<NumericOption>(every_numeric_option()); }
  static void TearDownTestSuite() {
    delete options_;
    options_ = nullptr;
  }
  void run_and_check(std::vector<Case> cases) {
#if defined(__SANITIZE_ADDRESS__)
    cases = one_case_per_option(std::move(cases));
#endif
    run_all(cases, dir_.path);
    for (const auto& c : cases) check(c);
    for (const auto& e : fs::directory_iterator(dir_.path)) ADD_FAILURE() << "created " << e.path();
  }

  static std::vector<NumericOption>* options_;
  const seqtopo::test_support::TempDir dir_;
};

std::vector<NumericOption>* NumericOptions::options_ = nullptr;

TEST_F(NumericOptions, HelpListsTheOptionsOfEveryCommand) {
  std::set<std::string> commands;
  for (const auto& o : *options_) commands.insert(o.command);
  for (const std::string c : {"align", "bench align", "bench scale", "fingerprint", "localize", "map", "match-strings",
                              "similarity", "simulate"}) {
    EXPECT_TRUE(commands.count(c)) << c << " has no numeric option in its --help";
  }
  std::set<std::string> labels;
  for (const auto& o : *options_) labels.insert(o.label());
  for (const std::string l : {"map --gap", "map --kappa", "map --min-separation", "map --contrast-offset",
                              "map --every", "map --threads", "localize --contrast-offset", "bench scale --sizes"}) {
    EXPECT_TRUE(labels.count(l)) << l;
  }
  for (const auto& [label, allowed] : kNegativeAllowed) {
#ifndef SEQTOPO_MPI_CLI
    if (label.rfind("sparse ", 0) == 0) continue;
#endif
    EXPECT_TRUE(labels.count(label)) << label << " is listed as taking negatives but is no option";
  }
  EXPECT_GT(options_->size(), 60U);
}

// NaN, infinity, numbers beyond the type, trailing garbage and negatives (unless the option takes them). The
// parser's own test (tests/core/test_parse_number.cpp) tries many more spellings; here every option of every
// command meets the main kinds.
TEST_F(NumericOptions, NonFiniteHugeNegativeAndGarbageAreRefused) {
  std::vector<Case> cases;
  for (const auto& o : *options_) {
    std::vector<std::string> bad = {"nan", "inf", "3x"};
    bad.emplace_back(o.type == "FLOAT" ? "1e999" : "18446744073709551616");
    if (!o.list) bad.emplace_back("1,2");
    for (const auto& value : bad) cases.push_back(make_case(o, value));
    const auto allowed = kNegativeAllowed.find(o.label());
    if (allowed != kNegativeAllowed.end()) {
      cases.push_back(make_case(o, allowed->second.first, false));
    } else {
      cases.push_back(make_case(o, "-1"));
    }
  }
  run_and_check(cases);
  EXPECT_GT(cases.size(), 400U);
}

// The range each option's error states is the range it enforces: the values just outside are refused, the
// values at and just inside the bounds accepted.
TEST_F(NumericOptions, RangesAreEnforcedAtTheirBounds) {
  std::vector<Case> probes;
  for (const auto& o : *options_) probes.push_back(make_case(o, "nan"));
  run_all(probes, dir_.path);
  std::vector<Case> cases;
  int with_range = 0;
  for (const auto& p : probes) {
    const NumericOption& o = *p.option;
    const auto range = stated_range(first_line(p.result.err));
    ASSERT_TRUE(range) << o.label() << ": the error does not state what it expects: " << p.result.err;
    const bool integer = o.type != "FLOAT";
    EXPECT_EQ(range->integer, integer) << o.label() << ": " << p.result.err;
    const double step = integer ? 1.0 : 1e-3;
    if (range->min) {
      ++with_range;
      const double outside = range->min_exclusive ? *range->min : *range->min - step;
      const double inside = range->min_exclusive ? *range->min + step : *range->min;
      if (!(o.type == "UINT" && outside < 0)) cases.push_back(make_case(o, number_text(outside, integer)));
      cases.push_back(make_case(o, number_text(inside, integer), false));
    }
    if (range->max) {
      ++with_range;
      const double outside = range->max_exclusive ? *range->max : *range->max + step;
      const double inside = range->max_exclusive ? *range->max - step : *range->max;
      cases.push_back(make_case(o, number_text(outside, integer)));
      cases.push_back(make_case(o, number_text(inside, integer), false));
    }
    if (o.word) cases.push_back(make_case(o, *o.word, false));
  }
  run_and_check(cases);
  EXPECT_GT(with_range, 40);
}

}  // namespace
