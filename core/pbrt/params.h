#pragma once
// A pbrt-v4 parameter list: `"type name" value` or `"type name" [ values ]`
// after a directive (pbrt-v4 src/pbrt/paramdict.h). Types: integer, float,
// bool, string, point2, vector2, point3, vector3, normal3 (normal), rgb,
// spectrum, blackbody, texture (pbrt-v3's point, vector, normal and color are
// read as point3, vector3, normal3 and rgb). A parameter nobody reads is
// reported by unused(), which the importer turns into one warning each.
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>
#include "core/pbrt/tokenizer.h"

namespace lb::pbrt {

struct Param {
  std::string type, name;
  std::vector<double> numbers;       // integer, float, point*, vector*, normal, rgb, blackbody, spectrum pairs
  std::vector<std::string> strings;  // string, texture, a named spectrum
  std::vector<bool> bools;
  int line = 0, column = 0;
  mutable bool used = false;
  std::string declaration() const { return "\"" + type + " " + name + "\""; }
};

// A colour as pbrt-v4 reads an `rgb`, `spectrum` or `blackbody` parameter,
// reduced to linear sRGB (lightbench renders in RGB).
struct ColorValue {
  glm::dvec3 rgb{0};
  std::string approximation;  // "" if exact, else what was approximated (for a warning)
};

class ParamSet {
 public:
  // Reads the parameters that follow a directive's fixed arguments.
  static ParamSet parse(Tokenizer& tokens);

  bool has(const std::string& name) const { return find(name) != nullptr; }
  double getFloat(const std::string& name, double fallback) const;
  long getInt(const std::string& name, long fallback) const;
  bool getBool(const std::string& name, bool fallback) const;
  std::string getString(const std::string& name, const std::string& fallback) const;
  std::optional<glm::dvec3> getPoint3(const std::string& name) const;
  // All numbers of a parameter of one of `types` (e.g. {"point3"}); empty if absent.
  std::vector<double> getNumbers(const std::string& name, const std::vector<std::string>& types, size_t multipleOf) const;
  std::vector<long> getInts(const std::string& name) const;
  // An rgb / spectrum / blackbody parameter; nullopt if absent. `illuminant`:
  // pbrt-v4 normalises light spectra to luminance 1 (times `scale`).
  std::optional<ColorValue> getColor(const std::string& name, bool illuminant) const;
  // A "texture name" parameter: the texture's name, or "".
  std::string getTexture(const std::string& name) const;
  const Param* find(const std::string& name) const;

  std::vector<const Param*> unused() const;
  void markAllUsed() const;
  [[noreturn]] void fail(const Param& p, const std::string& message) const;

  std::string file;
  std::vector<Param> params;

 private:
  const Param& expect(const Param& p, const std::vector<std::string>& types) const;
};

// pbrt-v4's named spectra that scenes use for conductors and glasses, as RGB
// (conductors: eta and k at 650, 550 and 450 nm from the tabulated data
// pbrt-v4 ships; glasses: the index at 587.6 nm). nullopt if unknown.
std::optional<glm::dvec3> namedSpectrum(const std::string& name);

// The linear sRGB colour of a blackbody at `kelvin`, scaled to luminance 1
// (pbrt-v4's lights normalise their spectrum to luminance 1).
glm::dvec3 blackbodyRgb(double kelvin);

}  // namespace lb::pbrt
