// Comments cite docs/testing.md by section number ("testing.md §3", "§3–4",
// "§2, §5") and the docs link to its headings by anchor (issue 39: fourteen
// test files cited "§2/§3…" of a file that had no numbered sections). Every
// cited number must be a "## N." heading of docs/testing.md and every
// link to "testing.md#…" one of its headings' anchors.
#include <gtest/gtest.h>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

namespace lb {
namespace {

namespace fs = std::filesystem;
const fs::path kRoot = LIGHTBENCH_SOURCE_DIR;

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The files that may cite testing.md: sources, tests, scripts and docs (not
// build outputs or data).
std::vector<fs::path> citingFiles() {
  std::vector<fs::path> files{kRoot / "README.md"};
  for (const char* dir : {"core", "integrators", "experiments", "tests", "python", "docs", "scripts"}) {
    if (!fs::exists(kRoot / dir)) continue;
    for (const auto& e : fs::recursive_directory_iterator(kRoot / dir)) {
      std::string ext = e.path().extension().string();
      if (e.path().string().find("/tests/data/") != std::string::npos) continue;
      if (ext == ".cpp" || ext == ".h" || ext == ".py" || ext == ".md" || ext == ".sh") files.push_back(e.path());
    }
  }
  return files;
}

// GitHub's heading anchor: lower case, ASCII punctuation but '-' and '_'
// dropped, spaces to '-'.
std::string anchorOf(std::string heading) {
  std::string out;
  for (unsigned char c : heading) {
    if (c >= 0x80 || std::isalnum(c) || c == '-' || c == '_') out += char(std::tolower(c));
    else if (c == ' ') out += '-';
  }
  return out;
}

struct Headings {
  std::set<int> numbers;
  std::set<std::string> anchors;
};

Headings testingHeadings() {
  Headings h;
  std::istringstream text(readFile(kRoot / "docs" / "testing.md"));
  std::string line;
  std::regex numbered(R"(^## (\d+)\. )");
  while (std::getline(text, line)) {
    if (line.rfind("#", 0) != 0) continue;
    std::smatch m;
    if (std::regex_search(line, m, numbered)) h.numbers.insert(std::stoi(m[1]));
    h.anchors.insert(anchorOf(line.substr(line.find_first_not_of('#') + 1)));
  }
  return h;
}

TEST(DocCitations, EverySectionCitedInTestingMdExists) {
  Headings h = testingHeadings();
  ASSERT_GE(h.numbers.size(), 5u) << "docs/testing.md lost its numbered sections";
  // "testing.md §3", "testing.md §3–4", "testing.md §2, §5", "testing.md, §1".
  std::regex citation("testing\\.md,? (§\\d+(?:(?:–|-)\\d+)?(?:, §\\d+(?:(?:–|-)\\d+)?)*)");
  std::regex number("(\\d+)(?:(?:–|-)(\\d+))?");
  int citations = 0;
  for (const fs::path& f : citingFiles()) {
    std::string text = readFile(f);
    for (std::sregex_iterator it(text.begin(), text.end(), citation), end; it != end; ++it) {
      std::string cited = (*it)[1];
      for (std::sregex_iterator n(cited.begin(), cited.end(), number); n != end; ++n) {
        int first = std::stoi((*n)[1]), last = (*n)[2].matched ? std::stoi((*n)[2]) : first;
        for (int k = first; k <= last; ++k) {
          ++citations;
          EXPECT_TRUE(h.numbers.count(k)) << f.lexically_relative(kRoot) << " cites testing.md §" << k
                                          << ", which docs/testing.md has no '## " << k << ".' heading for";
        }
      }
    }
  }
  EXPECT_GE(citations, 15) << "fewer citations than the tests make: the pattern no longer matches them";
}

TEST(DocCitations, EveryLinkToATestingMdHeadingExists) {
  Headings h = testingHeadings();
  std::regex link(R"(testing\.md#([A-Za-z0-9_-]+))");
  int links = 0;
  for (const fs::path& f : citingFiles()) {
    std::string text = readFile(f);
    for (std::sregex_iterator it(text.begin(), text.end(), link), end; it != end; ++it) {
      ++links;
      EXPECT_TRUE(h.anchors.count((*it)[1])) << f.lexically_relative(kRoot) << " links to testing.md#" << (*it)[1]
                                             << ", which is no heading of docs/testing.md";
    }
  }
  EXPECT_GE(links, 2);
}

}  // namespace
}  // namespace lb
