#pragma once
// Mitsuba BSDF plugins as lightbench materials (core/bsdfs/material_factory.cpp:
// diffuse, conductor, dielectric, thin_dielectric; GGX roughness; textures). Where the two differ (a
// Beckmann lobe, a tinted dielectric, a one-sided surface) a warning says
// what was approximated and how.
#include <yaml-cpp/yaml.h>
#include <map>
#include <string>
#include "core/mitsuba/xml_reader.h"

namespace lb::mitsuba {

// The material for BSDF element `n` (the nested one when wrapped in twosided);
// `ids` resolves <ref> to textures declared elsewhere.
YAML::Node translateBsdf(XmlContext& xml, pugi::xml_node n, bool twoSided,
                         const std::map<std::string, pugi::xml_node>& ids);

// A <texture> element, or a <ref> to one, as lightbench's `texture:` mapping
// (core/textures/texture.h); null for an unsupported one (warned, dropped).
YAML::Node translateTexture(XmlContext& xml, pugi::xml_node n, const std::map<std::string, pugi::xml_node>& ids);

// An index of refraction given as a number or by Mitsuba's name for it
// ("bk7", "water", "air", ...); -1 for an unknown name.
double namedIor(const std::string& name);

}  // namespace lb::mitsuba
