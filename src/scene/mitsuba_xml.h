// Reading values out of a Mitsuba 3 scene's XML elements: parameter substitution, numbers,
// vectors, colours and transforms. Private to src/scene (used by load_mitsuba.cpp).
// Format: https://mitsuba.readthedocs.io/en/stable/src/key_topics/scene_format.html
#pragma once

#include <tinyxml2.h>

#include <map>
#include <set>
#include <string>

#include "core/math.h"
#include "scene/loaders.h"

namespace multiray::detail {

using XmlElement = tinyxml2::XMLElement;

// What every element reader needs: the file (for messages), the options (for warnings)
// and the <default> parameters seen so far.
struct MitsubaContext {
  std::string path;  // the XML file
  const LoadOptions* options = nullptr;
  std::map<std::string, std::string> params;  // <default name value>
  std::set<std::string> warned;               // what warn_once() has already said

  // Throws InputError "<path>: line <n>: <what>".
  [[noreturn]] void fail(const XmlElement* e, const std::string& what) const;
  // One warning per distinct `key` per load (e.g. one per unsupported element type).
  void warn_once(const std::string& key, const std::string& what);

  // Attribute `name` of `e` with every $param replaced by its <default> value; an
  // unknown $param is an error. Returns `fallback` when the attribute is absent, and
  // fails when it is absent and `fallback` is null.
  std::string attr(const XmlElement* e, const char* name, const char* fallback = nullptr) const;

  // Numbers separated by commas and/or white space ("278, 273, -800"). Fails on anything
  // that is not a finite number.
  std::vector<double> numbers(const XmlElement* e, const std::string& text) const;
  // A <float>/<integer> value, or one number of a list.
  double number(const XmlElement* e, const std::string& text) const;
  // A point or vector: attributes x, y, z (missing ones `fallback`) or value="x, y, z"
  // (one number means all three).
  Vec3 vec3(const XmlElement* e, float fallback = 0.0f) const;

  // The linear-sRGB colour of a property element: <rgb value="r, g, b"> (or one value),
  // <spectrum value="v"> or wavelength:value pairs (mitsuba_spectrum.h; `radiance` picks
  // the emitter conversion), or <float>. Fails for other element types (a texture).
  Vec3 colour(const XmlElement* e, bool radiance) const;

  // A <transform> element: its children (translate, scale, rotate, matrix, lookat)
  // applied in document order, each one after those before it (Mitsuba's convention).
  Mat4 transform(const XmlElement* e) const;
};

// The first child element of `parent` whose name attribute is `name`, or null.
const XmlElement* named_child(const XmlElement* parent, const char* name);

// Whether element `e` is named `tag` (<tag ...>).
bool is(const XmlElement* e, const char* tag);

}  // namespace multiray::detail
