// `lightbench integrators NAME` lists what the settings readers read (issue 15):
// the listing is the reader run on an empty mapping, so these tests check the
// other direction — every listed key is accepted with its listed default, every
// listed range is enforced at its ends, an unlisted key is refused with the
// valid keys named — and that docs/integrators.md is the listing as generated.
#include <gtest/gtest.h>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include "integrators/registry.h"
#include "integrators/registry_docs.h"

namespace lb {
namespace {

// Builds `name` from `yaml` (integrator keys); the error message, or "" if accepted.
std::string tryCreate(const std::string& name, const std::string& yaml) {
  try {
    Params p(YAML::Load(yaml), "test.yaml", "integrator");
    makeIntegrator(name, p, "test.yaml", 1);
    return "";
  } catch (const ConfigError& e) {
    return e.what();
  }
}

// The keys a reader reads only under a condition need that condition set
// ("key: value", or "key: a or b", of which the first).
std::string conditionYaml(const KeyDoc& k) {
  if (k.condition.empty()) return "";
  auto colon = k.condition.find(':');
  std::string value = k.condition.substr(colon + 1);
  return k.condition.substr(0, colon) + ":" + value.substr(0, value.find(" or ")) + "\n";
}

TEST(IntegratorKeys, EveryIntegratorListsKeysWithMeaningAndType) {
  for (const auto& e : integratorRegistry()) {
    auto keys = integratorKeys(e.name);
    EXPECT_FALSE(keys.empty()) << e.name;
    for (const auto& k : keys) {
      EXPECT_FALSE(k.meaning.empty()) << e.name << "." << k.key << " has no meaning";
      EXPECT_TRUE(k.type == "number" || k.type == "integer" || k.type == "bool" || k.type == "choice" ||
                  k.type == "string")
          << e.name << "." << k.key << ": " << k.type;
    }
  }
}

TEST(IntegratorKeys, EveryListedKeyIsAcceptedWithItsListedDefault) {
  for (const auto& e : integratorRegistry())
    for (const auto& k : integratorKeys(e.name)) {
      std::string yaml = conditionYaml(k) + k.key + ": " + k.fallback;
      EXPECT_EQ(tryCreate(e.name, yaml), "") << e.name << ": " << yaml;
    }
}

TEST(IntegratorKeys, EveryListedChoiceIsAcceptedAndOthersRefused) {
  for (const auto& e : integratorRegistry())
    for (const auto& k : integratorKeys(e.name)) {
      if (k.type != "choice") continue;
      std::stringstream list(k.allowed);
      for (std::string c; std::getline(list >> std::ws, c, ',');)
        EXPECT_EQ(tryCreate(e.name, conditionYaml(k) + k.key + ": " + c), "") << e.name << "." << k.key << "=" << c;
      EXPECT_NE(tryCreate(e.name, conditionYaml(k) + k.key + ": not-a-choice"), "") << e.name << "." << k.key;
    }
}

// A range "[a, b]", "(a, b]", ">= a", "> a": the value at a closed end is
// accepted, the value at an open end and just beyond a closed end refused.
TEST(IntegratorKeys, EveryListedRangeIsEnforcedAtItsEnds) {
  int checked = 0;
  for (const auto& e : integratorRegistry())
    for (const auto& k : integratorKeys(e.name)) {
      if ((k.type != "number" && k.type != "integer") || k.allowed.empty()) continue;
      double step = k.type == "integer" ? 1 : 1e-3;
      auto check = [&](double value, bool ok) {
        std::ostringstream yaml;
        yaml << conditionYaml(k) << k.key << ": ";
        if (k.type == "integer") yaml << (long long)value;  // in full: 100000000, not 1e+08
        else yaml << std::setprecision(9) << value;  // a float's digits: 1e12 + 1e6 is not "1e+12"
        // Keys checked against each other (max_spacing >= min_spacing) are
        // given room on the other side.
        if (k.key == "max_spacing") yaml << "\nmin_spacing: 0";
        std::string err = tryCreate(e.name, yaml.str());
        if (ok) EXPECT_EQ(err, "") << e.name << ": " << yaml.str();
        else EXPECT_NE(err.find(k.key), std::string::npos) << e.name << ": " << yaml.str() << " accepted";
        ++checked;
      };
      double lo = 0, hi = 0;
      char open = 0, close = 0;
      if (std::sscanf(k.allowed.c_str(), "%lf, or >= %lf", &lo, &hi) == 2) {  // a value, or a half-line (k: 0, or >= 2)
        check(lo, true);
        check(lo - step, false);
        check(hi, true);
        check(hi - step, lo == hi - step);
      } else if (std::sscanf(k.allowed.c_str(), "%c%lf, %lf%c", &open, &lo, &hi, &close) == 4) {
        check(open == '(' ? lo : lo - step, false);
        // Just beyond a large end is a relative step (a float cannot hold 1e12 + 1e-3).
        check(close == ')' ? hi : hi + std::max(step, std::abs(hi) * 1e-6), false);
        if (open == '[') check(lo, true);
        if (close == ']') check(hi, true);
      } else if (std::sscanf(k.allowed.c_str(), ">= %lf", &lo) == 1) {
        check(lo, true);
        check(lo - step, false);
      } else if (std::sscanf(k.allowed.c_str(), "> %lf", &lo) == 1) {
        check(lo, false);
        check(lo + step, true);
      } else {
        ADD_FAILURE() << e.name << "." << k.key << ": unparsed range '" << k.allowed << "'";
      }
    }
  EXPECT_GT(checked, 40);
}

TEST(IntegratorKeys, AnUnknownKeyIsRefusedNamingTheValidOnes) {
  for (const auto& e : integratorRegistry()) {
    std::string key = integratorKeys(e.name).front().key;
    std::string err = tryCreate(e.name, key + "x: 3");  // a typo of a real key
    EXPECT_NE(err.find("did you mean '" + key + "'"), std::string::npos) << e.name << ": " << err;
    for (const auto& k : integratorKeys(e.name)) {
      if (k.condition.empty()) {
        EXPECT_NE(err.find(k.key), std::string::npos) << e.name << " does not list " << k.key;
      }
    }
  }
}

// An imported scene's max_depth goes to the integrators that read it (issue
// 39): integratorReadsKey is the listing, each integrator that lists
// max_depth takes it and each that does not refuses it, and an unknown name
// is left for makeIntegrator to refuse.
TEST(IntegratorKeys, ReadsKeyFollowsTheListing) {
  EXPECT_TRUE(integratorReadsKey("path", "max_depth"));
  EXPECT_FALSE(integratorReadsKey("direct", "max_depth"));
  EXPECT_TRUE(integratorReadsKey("no_such_integrator", "max_depth"));
  for (const auto& e : integratorRegistry()) {
    std::string err = tryCreate(e.name, "max_depth: 5");
    EXPECT_EQ(err.empty(), integratorReadsKey(e.name, "max_depth")) << e.name << ": " << err;
    EXPECT_EQ(keysReadBy(e.name)("max_depth"), integratorReadsKey(e.name, "max_depth"));
  }
}

// docs/integrators.md is, whole, what `lightbench integrators --markdown`
// prints; regenerate it (the test says how) when a reader changes.
TEST(IntegratorKeys, TheDocsAreTheGeneratedListing) {
  std::ifstream in(std::string(LIGHTBENCH_SOURCE_DIR) + "/docs/integrators.md");
  std::stringstream text;
  text << in.rdbuf();
  std::string generated;
  for (const auto& e : integratorRegistry()) generated += formatIntegratorKeys(e.name, true) + "\n";
  EXPECT_TRUE(text.str() == generated)
      << "docs/integrators.md is stale: run bash scripts/update-docs.sh";
}

// The docs' lists of integrators (all of them in README.md; by property:
// which split, which may render a reference, which --adaptive drives, which
// replay a sample; and those that cannot be split, with the reason) are
// generated (issue 39: four docs kept them by hand, and two had gone stale:
// `direct` and `guided` missing). Each sits between markers
//   <!-- integrators SPEC -->…<!-- /integrators -->
// and must be what `lightbench integrators SPEC` generates now.
TEST(IntegratorKeys, TheDocsListsOfIntegratorsAreGenerated) {
  namespace fs = std::filesystem;
  const fs::path root = LIGHTBENCH_SOURCE_DIR;
  std::vector<fs::path> files{root / "README.md"};
  for (const auto& e : fs::directory_iterator(root / "docs"))
    if (e.path().extension() == ".md") files.push_back(e.path());
  std::set<std::string> specs;
  for (const fs::path& f : files) {
    std::ifstream in(f);
    std::stringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    std::string current = withCurrentIntegratorLists(s, f.string());
    if (current != s) {  // name the first stale line, not the whole file
      size_t at = std::mismatch(s.begin(), s.end(), current.begin(), current.end()).first - s.begin();
      size_t from = s.rfind('\n', at == 0 ? 0 : at - 1);
      from = from == std::string::npos ? 0 : from + 1;
      ADD_FAILURE() << f.lexically_relative(root) << ":" << 1 + std::count(s.begin(), s.begin() + long(from), '\n')
                    << ": a stale list of integrators (run bash scripts/update-docs.sh):\n  is:        "
                    << s.substr(from, s.find('\n', at) - from) << "\n  generated: "
                    << current.substr(from, current.find('\n', at) - from);
    }
    std::regex marker("<!-- integrators ([^>]*) -->");
    for (std::sregex_iterator it(s.begin(), s.end(), marker), end; it != end; ++it) specs.insert((*it)[1]);
  }
  for (const std::string& p : integratorProperties()) EXPECT_TRUE(specs.count("--with " + p)) << "no docs list for '" << p << "'";
  EXPECT_TRUE(specs.count("--names"));
  EXPECT_TRUE(specs.count("--without splits"));
}

TEST(IntegratorKeys, MarkedListsAreFilledAndBadMarkersNamed) {
  std::string text = "a <!-- integrators --names -->old<!-- /integrators --> b\n"
                     "<!-- integrators --without splits -->\n- stale\n<!-- /integrators -->\n";
  std::string filled = withCurrentIntegratorLists(text, "x.md");
  EXPECT_EQ(filled, "a <!-- integrators --names -->" + integratorNames() + "<!-- /integrators --> b\n" +
                        "<!-- integrators --without splits -->\n" + integratorsWithout("splits") +
                        "<!-- /integrators -->\n");
  EXPECT_EQ(withCurrentIntegratorLists(filled, "x.md"), filled);
  EXPECT_THROW(withCurrentIntegratorLists("\n<!-- integrators --fast --><!-- /integrators -->", "x.md"), ConfigError);
  EXPECT_THROW(withCurrentIntegratorLists("<!-- integrators --names -->`path`", "x.md"), ConfigError);
}

// docs/integrator-guide.md explains each integrator in its own section
// ("## … (`name`)"), some with a table of the keys that matter most. Those
// tables are written by hand, so every key must be one the integrator reads,
// with the default it has (a row may pair keys: "`rr`, `rr_depth` | `true`, `3`").
TEST(IntegratorKeys, TheGuidesKeyTablesMatchTheCode) {
  std::ifstream in(std::string(LIGHTBENCH_SOURCE_DIR) + "/docs/integrator-guide.md");
  ASSERT_TRUE(in) << "docs/integrator-guide.md";
  std::regex section(R"(^## .*\(`([a-z_]+)`\)\s*$)"), row(R"(^\| (`[^|]*`) \| (`[^|]*`) \|)"), code("`([^`]*)`");
  auto quoted = [&](const std::string& cell) {
    std::vector<std::string> out;
    for (std::sregex_iterator it(cell.begin(), cell.end(), code), end; it != end; ++it) out.push_back((*it)[1]);
    return out;
  };
  std::string name, line;
  bool inKeyTable = false;
  int rows = 0, lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    std::smatch m;
    if (std::regex_match(line, m, section)) name = m[1];
    else if (line.rfind("## ", 0) == 0) name.clear();
    if (line == "| key | default | meaning |") inKeyTable = true;
    else if (line.empty()) inKeyTable = false;
    if (!inKeyTable || !std::regex_search(line, m, row)) continue;
    ASSERT_FALSE(name.empty()) << "integrator-guide.md:" << lineNumber << ": a key table outside an integrator's section";
    std::vector<std::string> keys = quoted(m[1]), defaults = quoted(m[2]);
    ASSERT_EQ(keys.size(), defaults.size()) << "integrator-guide.md:" << lineNumber;
    std::map<std::string, std::string> read;
    for (const KeyDoc& k : integratorKeys(name)) read[k.key] = k.fallback;
    for (size_t i = 0; i < keys.size(); ++i, ++rows) {
      ASSERT_TRUE(read.count(keys[i])) << "integrator-guide.md:" << lineNumber << ": " << name << " reads no key "
                                       << keys[i];
      EXPECT_EQ(defaults[i], read[keys[i]]) << "integrator-guide.md:" << lineNumber << ": " << name << "'s "
                                            << keys[i];
    }
  }
  EXPECT_GE(rows, 10);  // the path tracer's and BDPT's tables were read
}

TEST(IntegratorKeys, PropertyListsFollowTheInterface) {
  // Hand-checked facts the generator must reproduce: the variants come from
  // choice and bool keys, in both directions.
  // (Containment, not the whole list: a new integrator must not need this test edited.)
  std::string splits = integratorsWith("splits");
  for (const char* item : {"`path` (not with `regularize: true`), ", "`bdpt` (not with `mis: variance_aware` or `regularize: true`), ",
                           "`vcm` with `mode: bpt` or `mode: lvc` (not with `regularize: true`)"})
    EXPECT_NE(splits.find(item), std::string::npos) << item << " in " << splits;
  // A setting that takes the property away from every exception is named
  // too (mode: bpt is unbiased, regularized it is not).
  EXPECT_NE(integratorsWith("unbiased").find("`vcm` with `mode: bpt` (not with `regularize: true`)"), std::string::npos);
  for (const char* name : {"`sppm`", "`photon`", "`mlt`", "`irradiance_cache`"})
    EXPECT_EQ(splits.find(name), std::string::npos) << name << " in " << splits;
  EXPECT_NE(integratorsWith("adaptive").find(
                "`path` (not with `mis: variance_aware` or `engine: wavefront` or `rrs: adrrs` or `rrs: ears` or "
                "`regularize: true`)"),
            std::string::npos);
  EXPECT_EQ(integratorsWith("adaptive").find("`bdpt`"), std::string::npos);
  EXPECT_THROW(integratorsWith("fast"), ConfigError);
  // Those that cannot be split carry their own reason (splitRefusal()).
  std::string cannot = integratorsWithout("splits");
  EXPECT_NE(cannot.find("- `vcm` (not with `mode: bpt` or `mode: lvc`): its merging radius"), std::string::npos)
      << cannot;
  EXPECT_NE(cannot.find("- `vcm` with `mode: bpt` and `regularize: true`: regularize: its roughness"),
            std::string::npos)
      << cannot;
  EXPECT_NE(cannot.find("- `sppm`: each pass shrinks"), std::string::npos) << cannot;
  EXPECT_EQ(cannot.find("- `path`:"), std::string::npos) << cannot;
  EXPECT_NE(cannot.find("- `path` with `regularize: true`: regularize: its roughness"), std::string::npos) << cannot;
  EXPECT_NE(integratorsWithout("adaptive").find("- `path` with `engine: wavefront`: engine: wavefront traces"),
            std::string::npos);
  EXPECT_NE(integratorNames().find("`path`, `light`, `bdpt`"), std::string::npos);
}

}  // namespace
}  // namespace lb
