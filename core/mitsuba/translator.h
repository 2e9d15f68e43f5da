#pragma once
// The translation of one Mitsuba scene file, element by element: import.cpp
// reads the scene, its BSDFs, shapes and emitters; sensor.cpp the camera,
// film, sampler and integrator; bsdfs.cpp the BSDF plugins themselves.
#include <map>
#include <set>
#include <string>
#include "core/mitsuba/import.h"
#include "core/mitsuba/xml_reader.h"

namespace lb::mitsuba {

// What Mitsuba's unlimited path length becomes (always with a warning).
constexpr long kUnlimitedDepth = 100;

class Translator {
 public:
  Translator(std::string text, const std::string& path) : xml_(text, path), text_(std::move(text)) {}
  MitsubaImport run();

 private:
  void readIntegrator(pugi::xml_node n);
  void readSensor(pugi::xml_node n);
  void readSampler(pugi::xml_node n);
  void readFilm(pugi::xml_node n);
  YAML::Node readFilter(pugi::xml_node rfilter);
  std::string readBsdf(pugi::xml_node n, bool twoSided = false);
  std::string readWrapper(pugi::xml_node n, bool twoSided);
  std::string addMaterial(pugi::xml_node n, YAML::Node m, pugi::xml_node origin = {});
  // A shape of the scene, or, with `group`, of that shapegroup (the scene's
  // `objects:`, in the group's own space).
  void readShape(pugi::xml_node n, const std::string& group = "");
  void readShapeGroup(pugi::xml_node n);
  void readInstance(pugi::xml_node n, Props& p, const glm::dmat4& toWorld, bool inGroup);
  void readEmitter(pugi::xml_node n);
  void registerId(pugi::xml_node n);
  void origin(const std::string& key, pugi::xml_node n) { out_.origins.emplace_back(key, xml_.lineOf(n)); }

  XmlContext xml_;
  std::string text_;
  MitsubaImport out_;
  bool sensorSeen_ = false, integratorSeen_ = false;
  std::map<std::string, pugi::xml_node> ids_;        // every id: duplicates are errors, refs look up
  std::map<std::string, std::string> bsdfMaterial_;  // bsdf id → material name
  std::map<std::string, YAML::Node> groups_;         // shapegroup id → its shapes
  std::set<std::string> materialNames_;
  YAML::Node root_{YAML::NodeType::Map}, materials_{YAML::NodeType::Map};
  YAML::Node shapes_{YAML::NodeType::Sequence}, lights_{YAML::NodeType::Sequence};
};


}  // namespace lb::mitsuba
