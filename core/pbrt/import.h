#pragma once
// pbrt-v4 scene files (pbrt-v4 "User's Guide" and "File Format" pages, and
// src/pbrt/scene.cpp), translated into lightbench's scene description like
// Mitsuba's XML (core/scene_import.h): `lightbench render scene.pbrt`.
//
// The tokenizer and parser are written for the format (there is no Debian
// library for it): malformed input is one ConfigError naming
// file:line:column; each kind of unsupported directive, type or parameter
// is one warning naming it and what was done instead (--strict: an error).
//
// pbrt's conventions, and what lightbench makes of them (each is tested in
// tests/core/pbrt_import_test.cpp):
// - Matrices (`Transform`, `ConcatTransform`) are written column by column:
//   the last four numbers hold the translation. The current transformation
//   matrix (CTM) maps object space to world space; `Translate`, `Rotate`
//   (degrees, counter-clockwise about the axis), `Scale`, `LookAt` and
//   `ConcatTransform` multiply it on the right.
// - The CTM at `Camera` maps world to camera space, which is left-handed:
//   the camera looks down +z with +y up and +x to the image's right.
//   lightbench's image right is cross(forward, up), which for a
//   camera-to-world rotation is −x: such a camera (every `LookAt` camera)
//   becomes `handedness: left`, and one whose matrix mirrors (as Bitterli's
//   exports write it) stays `right`. Either way the image is pbrt's.
// - `fov` spans the image's shorter axis (fov_axis: smaller); default 90.
// - `maxdepth` counts bounces: 0 sees emitters only, 1 adds direct light.
//   lightbench's `max_depth` counts segments, so it is pbrt's + 1.
// - A triangle's geometric normal is the winding's, cross(p1 − p0, p2 − p0),
//   turned to the side of the shading normals `N` when a mesh has them, and
//   flipped by `ReverseOrientation` but not by a mirroring transform;
//   one-sided area lights emit on that side. Spheres and disks face out
//   (+z for a disk) unless ReverseOrientation and a mirroring CTM differ.
// - Light spectra are normalised to luminance 1 before `scale`: an `rgb` L
//   stays that RGB on an sRGB film; a `blackbody` L becomes its colour at
//   luminance 1. `power` (area, point, spot) and `illuminance` (distant,
//   infinite) rescale it to that power or illuminance.
// - `remaproughness` (default true) maps roughness to GGX alpha as
//   sqrt(roughness) (pbrt-v4 TrowbridgeReitzDistribution::RoughnessToAlpha).
// - Texture coordinates stay pbrt's; an imagemap is looked up at (s, 1 − t),
//   which its uv_transform does (materials.cpp).
// - Relative file names resolve against the folder of the file given on
//   the command line, also inside `Include`d files (pbrt-v4's search
//   directory).
#include <string>
#include "core/scene_import.h"

namespace lb {

// True for a path ending in ".pbrt" (any case).
bool isPbrtPath(const std::string& path);
ImportedScene importPbrt(const std::string& path);
// For tests and the fuzzer: relative file names resolve against virtualPath's
// folder; `Include` reads real files there.
ImportedScene importPbrtFromString(const std::string& text, const std::string& virtualPath);

}  // namespace lb
