#pragma once
// What the docs say about the integrators, generated from the registry and
// the integrator interface so that it cannot go stale (issue 39): the key
// tables of docs/integrators.md, and the lists of integrators marked in
// README.md and docs/*.md as
//   <!-- integrators SPEC -->…<!-- /integrators -->
// where SPEC is what `lightbench integrators SPEC` prints:
//   --names             every registered integrator: "`path`, `light`, …"
//   --with PROPERTY     those with a property, on one line
//   --without PROPERTY  those without it, one "- `name`: why" line each
// and the properties are
//   splits    `render --distributed` splits it into chunks (splitRefusal() "")
//   unbiased  it may render an experiment's reference (IntegratorEntry::unbiased)
//   adaptive  `--adaptive` / `adaptive:` can drive it (adaptiveRefusal() "")
//   replay    `--pixel X,Y --sample I` replays one of its samples (replaysSamples())
// Each integrator is tried at its defaults and with each value of each of its
// choice keys: "`path`, `vcm` with `mode: bpt`, `guided` (not with `method:
// qlearning`)". `bash scripts/update-docs.sh` rewrites every marked list and
// docs/integrators.md; tests/integrators/registry_keys_test.cpp fails while
// one is stale.
#include <string>
#include <vector>

namespace lb {

const std::vector<std::string>& integratorProperties();
// Throw ConfigError for an unknown property.
std::string integratorsWith(const std::string& property);
std::string integratorsWithout(const std::string& property);
std::string integratorNames();
// `text` (a markdown file's) with every marked list as it is generated now.
// Throws ConfigError (naming `file` and the line) for an unknown SPEC or a
// list without its closing marker.
std::string withCurrentIntegratorLists(const std::string& text, const std::string& file);
// The table `lightbench integrators NAME` prints; markdown for docs/integrators.md.
std::string formatIntegratorKeys(const std::string& name, bool markdown);

}  // namespace lb
