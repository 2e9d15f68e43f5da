#pragma once
// The translation of one pbrt-v4 scene, directive by directive: import.cpp
// reads the file structure, transforms, attributes and instancing; options.cpp
// the camera, film, sampler, filter and integrator; shapes.cpp shapes and
// lights; materials.cpp materials and textures.
#include <glm/glm.hpp>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>
#include "core/pbrt/params.h"
#include "core/scene_import.h"

namespace lb::pbrt {

// Where a directive was written: its own file and line, and the line in the
// main file that reached it (itself, or the Include that read its file).
struct Where {
  std::string file;
  int line = 0, column = 0;
  int mainLine = 0;
  std::string element;  // e.g. Shape "sphere"
};

struct AreaLight {
  glm::dvec3 radiance{0};  // L × scale (normalised as pbrt-v4 does)
  bool twoSided = false;
  double power = -1;  // `power`: rescale to this many watts once the area is known
  Where at;
};

// pbrt's graphics state: what AttributeBegin saves and AttributeEnd restores.
struct GraphicsState {
  glm::dmat4 ctm{1.0};
  bool reverseOrientation = false;
  std::string material;  // a lightbench material name; "" is pbrt's default (diffuse 0.5)
  std::optional<AreaLight> areaLight;
};


class Translator {
 public:
  explicit Translator(std::string mainPath);
  ImportedScene run(const std::string& text);

 private:
  // import.cpp
  void parse(Tokenizer& tokens, int includeDepth, int mainLine);
  void directive(const Token& name, Tokenizer& tokens, int includeDepth, int mainLine);
  void include(const Token& directive, Tokenizer& tokens, int includeDepth, int mainLine);
  void warn(const Where& at, const std::string& message);
  // Warns once for each parameter nobody read.
  void warnUnused(const ParamSet& ps, const Where& at);
  // options.cpp
  void camera(const std::string& type, const ParamSet& ps, const Where& at);
  void film(const std::string& type, const ParamSet& ps, const Where& at);
  void sampler(const std::string& type, const ParamSet& ps, const Where& at);
  void pixelFilter(const std::string& type, const ParamSet& ps, const Where& at);
  void integrator(const std::string& type, const ParamSet& ps, const Where& at);
  // shapes.cpp
  void shape(const std::string& type, const ParamSet& ps, const GraphicsState& gs, const Where& at);
  void lightSource(const std::string& type, const ParamSet& ps, const Where& at);
  AreaLight areaLightSource(const std::string& type, const ParamSet& ps, const Where& at);
  // materials.cpp: the lightbench material for a pbrt material of `type`.
  YAML::Node material(const std::string& type, const ParamSet& ps, const Where& at);
  std::string addMaterial(const std::string& preferredName, YAML::Node m);
  // A Texture directive as lightbench's `texture:` mapping; null (warned) if not read.
  YAML::Node texture(const std::string& texClass, const std::string& type, const ParamSet& ps, const Where& at);

  std::string mainPath_, folder_;
  ImportedScene out_;
  ImportWarnings warnings_;

  GraphicsState gs_;
  // What AttributeBegin ('a'), TransformBegin ('t', pbrt-v3; pbrt-v4 reads it
  // as AttributeBegin) and ObjectBegin ('o') saved: each End must match its Begin.
  std::vector<std::pair<char, GraphicsState>> attributeStack_;
  std::map<std::string, glm::dmat4> namedCoordinateSystems_;
  std::map<std::string, std::string> namedMaterials_;  // pbrt name → lightbench name
  std::set<std::string> materialNames_;
  std::set<std::string> interfaceMaterials_;
  bool interfaceNext_ = false;  // set by material(): the material being added is an interface  // pbrt's interface/none: no surface, so no area light either
  std::map<std::string, YAML::Node> namedTextures_;       // spectrum textures read (imagemap, checkerboard)
  std::map<std::string, YAML::Node> namedFloatTextures_;  // float ones (displacement, alpha)
  std::map<std::string, std::string> alphaMaterials_;     // (material, alpha) → its copy with that opacity
  // ObjectBegin/End: each object's shapes, in the object's space (their CTM
  // inside it), written to the scene's `objects:`; ObjectInstance places one
  // as a `type: instance` shape (Embree instancing, core/scene.h).
  std::map<std::string, YAML::Node> objects_;  // each a sequence of shapes
  std::string currentObject_;  // inside ObjectBegin, else ""
  bool inWorld_ = false, cameraSeen_ = false, filmSeen_ = false, samplerSeen_ = false, filterSeen_ = false,
       integratorSeen_ = false;
  YAML::Node root_{YAML::NodeType::Map}, materials_{YAML::NodeType::Map};
  YAML::Node shapes_{YAML::NodeType::Sequence}, lights_{YAML::NodeType::Sequence};
  YAML::Node filter_;  // the film's filter, set by PixelFilter
  int includedFiles_ = 0;
};

}  // namespace lb::pbrt
