#pragma once
// What the pbrt and Mitsuba importers' instancing tests both expect of a
// translated scene (pbrt_import_test.cpp, mitsuba_instancing_test.cpp).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>
#include <string>

namespace lb::test {

// The scene defines an object "lamp" (an emitting sphere) and an object
// "nothing" (whose every shape was dropped), and instances each once: the
// lamp is kept without its emission (instances do not emit), and "nothing"
// is neither an object nor placed.
inline void expectLampWithoutEmissionAndNothingPlaced(const YAML::Node& scene) {  // const: look-ups add no keys
  ASSERT_TRUE(scene["objects"]["lamp"]);
  EXPECT_FALSE(scene["objects"]["lamp"][0]["emission"]);
  EXPECT_FALSE(scene["objects"]["nothing"]);
  ASSERT_EQ(scene["shapes"].size(), 1u);
  EXPECT_EQ(scene["shapes"][0]["object"].as<std::string>(), "lamp");
}

}  // namespace lb::test
