#pragma once
// Mitsuba BSDF plugins as lightbench materials (core/bsdfs/material_factory.cpp:
// diffuse, conductor, dielectric; GGX roughness). Where the two differ (a
// Beckmann lobe, a tinted dielectric, a one-sided surface) a warning says
// what was approximated and how.
#include <yaml-cpp/yaml.h>
#include <string>
#include "core/mitsuba/xml_reader.h"

namespace lb::mitsuba {

// The material for BSDF element `n` (the nested one when wrapped in twosided).
YAML::Node translateBsdf(XmlContext& xml, pugi::xml_node n, bool twoSided);

// An index of refraction given as a number or by Mitsuba's name for it
// ("bk7", "water", "air", ...); -1 for an unknown name.
double namedIor(const std::string& name);

}  // namespace lb::mitsuba
