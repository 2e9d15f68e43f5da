#include "core/pbrt/params.h"
#include <algorithm>
#include <cmath>
#include <map>
#include "core/bsdfs/named_conductors.h"
#include "core/error.h"

namespace lb::pbrt {
namespace {

// pbrt-v3 spellings pbrt-v4 still reads, and the type each stands for.
std::string canonicalType(const std::string& t) {
  if (t == "point") return "point3";
  if (t == "vector") return "vector3";
  if (t == "normal") return "normal3";
  if (t == "color") return "rgb";
  return t;
}

bool knownType(const std::string& t) {
  static const char* types[] = {"integer", "float",  "bool",     "string",    "point2", "vector2", "point3",
                                "vector3", "normal3", "rgb", "spectrum", "blackbody", "texture"};
  return std::find(std::begin(types), std::end(types), t) != std::end(types);
}

// The CIE 1931 colour matching functions as Wyman, Sloan and Shirley's
// multi-lobe Gaussian fit ("Simple Analytic Approximations to the CIE XYZ
// Color Matching Functions", JCGT 2(2), 2013, eq. 2): within about 1 % of
// the tables, enough for a light's colour.
glm::dvec3 cieXyz(double nm) {
  auto g = [nm](double mu, double s1, double s2) {
    double t = (nm - mu) / (nm < mu ? s1 : s2);
    return std::exp(-0.5 * t * t);
  };
  return {1.056 * g(599.8, 37.9, 31.0) + 0.362 * g(442.0, 16.0, 26.7) - 0.065 * g(501.1, 20.4, 26.2),
          0.821 * g(568.8, 46.9, 40.5) + 0.286 * g(530.9, 16.3, 31.1),
          1.217 * g(437.0, 11.8, 36.0) + 0.681 * g(459.0, 26.0, 13.8)};
}

// XYZ (D65 white) to linear sRGB (IEC 61966-2-1).
glm::dvec3 xyzToSrgb(glm::dvec3 c) {
  return {3.2406 * c.x - 1.5372 * c.y - 0.4986 * c.z, -0.9689 * c.x + 1.8758 * c.y + 0.0415 * c.z,
          0.0557 * c.x - 0.2040 * c.y + 1.0570 * c.z};
}

// ∫ spectrum · (x̄, ȳ, z̄) over 360–830 nm, 1 nm steps.
template <class F>
glm::dvec3 integrateXyz(F&& spectrum) {
  glm::dvec3 sum(0);
  for (double nm = 360; nm <= 830; nm += 1) sum += spectrum(nm) * cieXyz(nm);
  return sum;
}

}  // namespace

glm::dvec3 blackbodyRgb(double kelvin) {
  // Planck's law; constants cancel in the normalisation but keep it finite.
  auto planck = [kelvin](double nm) {
    const double c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23, l = nm * 1e-9;
    return 2 * h * c * c / (std::pow(l, 5) * (std::exp(h * c / (l * kb * kelvin)) - 1)) * 1e-13;
  };
  glm::dvec3 xyz = integrateXyz(planck);
  if (!(xyz.y > 0) || !std::isfinite(xyz.y)) return glm::dvec3(std::nan(""));  // too cold to see: the caller refuses it
  glm::dvec3 rgb = xyzToSrgb(xyz / xyz.y);
  return {std::max(rgb.r, 0.0), std::max(rgb.g, 0.0), std::max(rgb.b, 0.0)};
}

std::optional<glm::dvec3> namedSpectrum(const std::string& name) {
  // metal-<symbol>-eta / metal-<symbol>-k
  if (name.rfind("metal-", 0) == 0) {
    size_t dash = name.rfind('-');
    std::string symbol = name.substr(6, dash - 6), part = name.substr(dash + 1);
    if (const ComplexIor* m = namedConductor(symbol)) {
      if (part == "eta") return m->eta;
      if (part == "k") return m->k;
    }
    return std::nullopt;
  }
  // Schott glasses at the d line (587.6 nm), from Schott's data sheets; pbrt-v4's
  // glass-F5, F10 and F11 hold the data of SF5, SF10 and SF11.
  static const std::map<std::string, double> glasses = {
      {"glass-BK7", 1.5168},   {"glass-BAF10", 1.6700}, {"glass-FK51A", 1.4866}, {"glass-LASF9", 1.8503},
      {"glass-F5", 1.6727},    {"glass-F10", 1.7283},   {"glass-F11", 1.7847}};
  if (auto it = glasses.find(name); it != glasses.end()) return glm::dvec3(it->second);
  return std::nullopt;
}

ParamSet ParamSet::parse(Tokenizer& tokens) {
  ParamSet set;
  set.file = tokens.file();
  while (tokens.peek().kind == Token::Kind::String) {
    Token decl = tokens.next();
    Param p;
    p.line = decl.line, p.column = decl.column;
    // "type name", separated by spaces.
    std::vector<std::string> words;
    size_t i = 0;
    while (i < decl.text.size()) {
      while (i < decl.text.size() && std::isspace(static_cast<unsigned char>(decl.text[i]))) ++i;
      size_t j = i;
      while (j < decl.text.size() && !std::isspace(static_cast<unsigned char>(decl.text[j]))) ++j;
      if (j > i) words.push_back(decl.text.substr(i, j - i));
      i = j;
    }
    if (words.size() != 2)
      tokens.fail(decl, "expected a parameter declaration \"type name\" (e.g. \"float radius\"), got \"" + decl.text + "\"");
    p.type = canonicalType(words[0]), p.name = words[1];
    if (!knownType(p.type))
      tokens.fail(decl, "unknown parameter type '" + words[0] +
                            "' (integer, float, bool, string, point2, vector2, point3, vector3, normal3, rgb, spectrum, blackbody, texture)");
    for (const Param& q : set.params)
      if (q.name == p.name) tokens.fail(decl, "parameter '" + p.name + "' given twice");
    // One value, or a bracketed list of them.
    std::vector<Token> values;
    const Token& first = tokens.peek();
    if (first.kind == Token::Kind::OpenBracket) {
      tokens.next();
      for (;;) {
        Token v = tokens.next();
        if (v.kind == Token::Kind::CloseBracket) break;
        if (v.kind == Token::Kind::End) tokens.fail(v, "end of file inside the values of " + p.declaration() + " (missing ']')");
        if (v.kind == Token::Kind::OpenBracket) tokens.fail(v, "'[' inside the values of " + p.declaration());
        values.push_back(std::move(v));
      }
    } else if (first.kind == Token::Kind::String || first.kind == Token::Kind::Word) {
      values.push_back(tokens.next());
    } else {
      tokens.fail(first, "expected a value or '[' after " + p.declaration());
    }
    bool stringValued = p.type == "string" || p.type == "texture" ||
                        (p.type == "spectrum" && !values.empty() && values[0].kind == Token::Kind::String);
    for (const Token& v : values) {
      if (stringValued) {
        if (v.kind != Token::Kind::String) tokens.fail(v, "expected a quoted string in " + p.declaration() + ", got '" + v.text + "'");
        p.strings.push_back(v.text);
      } else if (p.type == "bool") {
        if (v.text != "true" && v.text != "false")
          tokens.fail(v, "expected true or false in " + p.declaration() + ", got '" + v.text + "'");
        p.bools.push_back(v.text == "true");
      } else {
        double x = 0;
        if (v.kind != Token::Kind::Word || !parseNumber(v.text, x))
          tokens.fail(v, "expected a finite number in " + p.declaration() + ", got '" + v.text + "'");
        if (p.type == "integer" && (x != std::floor(x) || std::abs(x) > 2147483647.0))
          tokens.fail(v, "expected an integer in " + p.declaration() + ", got '" + v.text + "'");
        p.numbers.push_back(x);
      }
    }
    if (values.empty()) tokens.fail(first, "no value for " + p.declaration());
    set.params.push_back(std::move(p));
  }
  return set;
}

const Param* ParamSet::find(const std::string& name) const {
  for (const Param& p : params)
    if (p.name == name) {
      p.used = true;
      return &p;
    }
  return nullptr;
}

void ParamSet::fail(const Param& p, const std::string& message) const {
  throw ConfigError(file, p.line, p.column, p.name, message);
}

const Param& ParamSet::expect(const Param& p, const std::vector<std::string>& types) const {
  if (std::find(types.begin(), types.end(), p.type) == types.end()) {
    std::string list;
    for (const std::string& t : types) list += (list.empty() ? "" : " or ") + t;
    fail(p, "expected a " + list + " parameter, got " + p.type);
  }
  return p;
}

double ParamSet::getFloat(const std::string& name, double fallback) const {
  const Param* p = find(name);
  if (!p) return fallback;
  expect(*p, {"float", "integer"});
  if (p->numbers.size() != 1) fail(*p, "expected one number, got " + std::to_string(p->numbers.size()));
  return p->numbers[0];
}

long ParamSet::getInt(const std::string& name, long fallback) const {
  const Param* p = find(name);
  if (!p) return fallback;
  expect(*p, {"integer"});
  if (p->numbers.size() != 1) fail(*p, "expected one integer, got " + std::to_string(p->numbers.size()));
  return long(p->numbers[0]);
}

bool ParamSet::getBool(const std::string& name, bool fallback) const {
  const Param* p = find(name);
  if (!p) return fallback;
  expect(*p, {"bool"});
  if (p->bools.size() != 1) fail(*p, "expected one bool, got " + std::to_string(p->bools.size()));
  return p->bools[0];
}

std::string ParamSet::getString(const std::string& name, const std::string& fallback) const {
  const Param* p = find(name);
  if (!p) return fallback;
  expect(*p, {"string"});
  if (p->strings.size() != 1) fail(*p, "expected one string, got " + std::to_string(p->strings.size()));
  return p->strings[0];
}

std::string ParamSet::getTexture(const std::string& name) const {
  const Param* p = find(name);
  if (!p || p->type != "texture") return "";
  if (p->strings.size() != 1) fail(*p, "expected one texture name, got " + std::to_string(p->strings.size()));
  return p->strings[0];
}

std::optional<glm::dvec3> ParamSet::getPoint3(const std::string& name) const {
  std::vector<double> v = getNumbers(name, {"point3", "vector3", "normal3"}, 3);
  if (v.empty()) return std::nullopt;
  if (v.size() != 3) fail(*find(name), "expected one 3D point (3 numbers), got " + std::to_string(v.size()));
  return glm::dvec3(v[0], v[1], v[2]);
}

std::vector<double> ParamSet::getNumbers(const std::string& name, const std::vector<std::string>& types, size_t multipleOf) const {
  const Param* p = find(name);
  if (!p) return {};
  expect(*p, types);
  if (p->numbers.size() % multipleOf != 0)
    fail(*p, "expected a multiple of " + std::to_string(multipleOf) + " numbers, got " + std::to_string(p->numbers.size()));
  return p->numbers;
}

std::vector<long> ParamSet::getInts(const std::string& name) const {
  std::vector<double> v = getNumbers(name, {"integer"}, 1);
  return std::vector<long>(v.begin(), v.end());
}

std::optional<ColorValue> ParamSet::getColor(const std::string& name, bool illuminant) const {
  const Param* p = find(name);
  if (!p) return std::nullopt;
  expect(*p, {"rgb", "spectrum", "blackbody", "float"});
  ColorValue c;
  if (p->type == "rgb") {
    if (p->numbers.size() != 3) fail(*p, "expected 3 numbers (r g b), got " + std::to_string(p->numbers.size()));
    c.rgb = {p->numbers[0], p->numbers[1], p->numbers[2]};
    // pbrt-v4 reads an illuminant's rgb as rgb × its colour space's white
    // (D65), normalised by that white's luminance: the same rgb on an sRGB film.
  } else if (p->type == "float") {
    if (p->numbers.size() != 1) fail(*p, "expected one number, got " + std::to_string(p->numbers.size()));
    c.rgb = glm::dvec3(p->numbers[0]);
  } else if (p->type == "blackbody") {
    if (p->numbers.size() != 1 || !(p->numbers[0] >= 500 && p->numbers[0] <= 1e6))
      fail(*p, "expected one temperature in kelvin, in [500, 1e6] (a visible blackbody)");
    c.rgb = blackbodyRgb(p->numbers[0]);
    c.approximation = "a blackbody as its linear sRGB colour at luminance 1";
  } else if (!p->strings.empty()) {
    if (p->strings.size() != 1) fail(*p, "expected one spectrum name, got " + std::to_string(p->strings.size()));
    const std::string& s = p->strings[0];
    if (auto v = namedSpectrum(s)) {
      c.rgb = *v;
    } else if (s.rfind("stdillum-", 0) == 0 && illuminant) {
      // Normalised to luminance 1 as every pbrt-v4 light spectrum is.
      c.rgb = s == "stdillum-A" ? blackbodyRgb(2856) : glm::dvec3(1);
      if (s != "stdillum-D65") c.approximation = "illuminant '" + s + "' as " + (s == "stdillum-A" ? "a 2856 K blackbody" : "white (D65)");
    } else {
      fail(*p, "unknown named spectrum '" + s + "' (lightbench knows metal-{Au,Ag,Cu,Al}-{eta,k}, glass-{BK7,BAF10,FK51A,LASF9,F5,F10,F11}, stdillum-*; not .spd files)");
    }
  } else if (p->numbers.size() == 1) {
    c.rgb = glm::dvec3(p->numbers[0]);  // a constant spectrum
  } else {
    // (wavelength, value) pairs, piecewise linear, as a colour.
    if (p->numbers.size() < 4 || p->numbers.size() % 2 != 0)
      fail(*p, "expected (wavelength value) pairs, at least two, got " + std::to_string(p->numbers.size()) + " numbers");
    for (size_t i = 2; i < p->numbers.size(); i += 2)
      if (!(p->numbers[i] > p->numbers[i - 2])) fail(*p, "wavelengths must increase");
    const std::vector<double>& v = p->numbers;
    auto at = [&](double nm) {
      if (nm <= v[0]) return v[1];
      if (nm >= v[v.size() - 2]) return v.back();
      size_t i = 2;
      while (v[i] < nm) i += 2;
      double t = (nm - v[i - 2]) / (v[i] - v[i - 2]);
      return v[i - 1] * (1 - t) + v[i + 1] * t;
    };
    glm::dvec3 xyz = integrateXyz(at), white = integrateXyz([](double) { return 1.0; });
    // Under an equal-energy white; an illuminant is normalised to luminance 1.
    c.rgb = glm::max(xyzToSrgb(illuminant ? xyz / std::max(xyz.y, 1e-300) : xyz / white.y), glm::dvec3(0));
    c.approximation = "a sampled spectrum as its linear sRGB colour";
  }
  if (!std::isfinite(c.rgb.r + c.rgb.g + c.rgb.b)) fail(*p, "the colour is not finite");
  return c;
}

std::vector<const Param*> ParamSet::unused() const {
  std::vector<const Param*> out;
  for (const Param& p : params)
    if (!p.used) out.push_back(&p);
  return out;
}

void ParamSet::markAllUsed() const {
  for (const Param& p : params) p.used = true;
}

}  // namespace lb::pbrt
