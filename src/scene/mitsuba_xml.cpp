#include "scene/mitsuba_xml.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>

#include "scene/mitsuba_spectrum.h"

namespace multiray::detail {
namespace {

Mat4 from_rows(const double* v, int n) {  // n = 3 (3x3) or 4 (4x4), row-major
  Mat4 m;
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) m.m[r][c] = float(v[r * n + c]);
  return m;
}

// Mitsuba's look-at frame: local +z towards the target, +y towards `up`, and +x =
// up x z, which the perspective sensor shows on the image's LEFT (its screen x axis is
// flipped). So eye/target/up taken from this matrix give the same picture in our
// right-handed pinhole, whose image right is forward x up (= local -x).
Mat4 look_at(Vec3 origin, Vec3 target, Vec3 up, bool* ok) {
  const Vec3 dir = normalize(target - origin);
  const Vec3 left_raw = cross(up, dir);
  *ok = length(target - origin) > 0 && length(left_raw) > 1e-6f * length(up);
  const Vec3 left = normalize(left_raw), new_up = cross(dir, left);
  Mat4 m;
  for (int r = 0; r < 3; ++r) {
    m.m[r][0] = left[r], m.m[r][1] = new_up[r], m.m[r][2] = dir[r], m.m[r][3] = origin[r];
  }
  return m;
}

// Rotation by `deg` degrees about `axis`, counter-clockwise looking down the axis
// (Rodrigues' formula).
Mat4 rotation(Vec3 axis, double deg) {
  const Vec3 a = normalize(axis);
  const double t = deg * kPi / 180.0, c = std::cos(t), s = std::sin(t);
  const double k[3][3] = {{0, -a.z, a.y}, {a.z, 0, -a.x}, {-a.y, a.x, 0}};
  Mat4 m;
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 3; ++col)
      m.m[r][col] = float((r == col ? c : 0.0) + s * k[r][col] + (1 - c) * a[r] * a[col]);
  return m;
}

}  // namespace

void MitsubaContext::fail(const XmlElement* e, const std::string& what) const {
  detail::fail(path, (e ? "line " + std::to_string(e->GetLineNum()) + ": " : "") + what);
}

void MitsubaContext::warn_once(const std::string& key, const std::string& what) {
  if (warned.insert(key).second) detail::warn(*options, path, what);
}

std::string MitsubaContext::attr(const XmlElement* e, const char* name,
                                 const char* fallback) const {
  const char* raw = e->Attribute(name);
  if (raw == nullptr) {
    if (fallback == nullptr) fail(e, std::string("<") + e->Name() + "> needs '" + name + "'");
    return fallback;
  }
  std::string out;
  for (const char* p = raw; *p;) {
    if (*p != '$') {
      out += *p++;
      continue;
    }
    const char* q = ++p;
    while (std::isalnum(static_cast<unsigned char>(*q)) || *q == '_') ++q;
    const auto it = params.find(std::string(p, q));
    if (q == p || it == params.end())
      fail(e, "undefined parameter '$" + std::string(p, q) + "' (no <default> for it)");
    out += it->second;
    p = q;
  }
  return out;
}

std::vector<double> MitsubaContext::numbers(const XmlElement* e, const std::string& text) const {
  std::vector<double> out;
  const char* p = text.data();
  const char* end = p + text.size();
  while (true) {
    while (p < end && (std::isspace(static_cast<unsigned char>(*p)) || *p == ',')) ++p;
    if (p == end) return out;
    double v = 0;
    const auto [next, ec] = std::from_chars(p, end, v);
    if (ec != std::errc() || !std::isfinite(v) ||
        (next < end && !std::isspace(static_cast<unsigned char>(*next)) && *next != ','))
      fail(e, "'" + text + "' is not a list of numbers");
    out.push_back(v);
    p = next;
  }
}

double MitsubaContext::number(const XmlElement* e, const std::string& text) const {
  const std::vector<double> v = numbers(e, text);
  if (v.size() != 1) fail(e, "'" + text + "' is not one number");
  return v[0];
}

Vec3 MitsubaContext::vec3(const XmlElement* e, float fallback) const {
  if (e->Attribute("value")) {
    const std::vector<double> v = numbers(e, attr(e, "value"));
    if (v.size() == 1) return Vec3(float(v[0]));
    if (v.size() != 3) fail(e, "<" + std::string(e->Name()) + "> needs 1 or 3 numbers");
    return Vec3(float(v[0]), float(v[1]), float(v[2]));
  }
  Vec3 out(fallback);
  const char* names[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    if (e->Attribute(names[i])) out[i] = float(number(e, attr(e, names[i])));
  return out;
}

Vec3 MitsubaContext::colour(const XmlElement* e, bool radiance) const {
  if (is(e, "float")) return Vec3(float(number(e, attr(e, "value"))));
  if (is(e, "rgb")) return vec3(e);
  if (!is(e, "spectrum")) fail(e, "<" + std::string(e->Name()) + "> is not a supported colour");
  const std::string text = attr(e, "value");
  if (text.find(':') == std::string::npos) return Vec3(float(number(e, text)));
  SampledSpectrum s;
  const std::string problem = parse_spectrum_pairs(text, &s);
  if (!problem.empty()) fail(e, "spectrum: " + problem);
  return radiance ? radiance_spectrum_to_rgb(s) : reflectance_spectrum_to_rgb(s);
}

Mat4 MitsubaContext::transform(const XmlElement* t) const {
  Mat4 m;
  for (const XmlElement* e = t->FirstChildElement(); e; e = e->NextSiblingElement()) {
    Mat4 step;
    if (is(e, "translate")) {
      const Vec3 v = vec3(e);
      for (int r = 0; r < 3; ++r) step.m[r][3] = v[r];
    } else if (is(e, "scale")) {
      const Vec3 v = vec3(e, 1.0f);
      for (int r = 0; r < 3; ++r) step.m[r][r] = v[r];
    } else if (is(e, "rotate")) {
      const Vec3 axis = vec3(e);
      if (!(length(axis) > 0)) fail(e, "<rotate> needs a non-zero axis");
      step = rotation(axis, number(e, attr(e, "angle")));
    } else if (is(e, "matrix")) {
      const std::vector<double> v = numbers(e, attr(e, "value"));
      if (v.size() != 16 && v.size() != 9) fail(e, "<matrix> needs 16 (or 9) numbers");
      step = from_rows(v.data(), v.size() == 16 ? 4 : 3);
    } else if (is(e, "lookat")) {
      auto point = [&](const char* name, const char* fallback) {
        const std::vector<double> v = numbers(e, attr(e, name, fallback));
        if (v.size() != 3) fail(e, std::string("<lookat> ") + name + " needs 3 numbers");
        return Vec3(float(v[0]), float(v[1]), float(v[2]));
      };
      bool ok = false;
      step =
          look_at(point("origin", nullptr), point("target", nullptr), point("up", "0, 1, 0"), &ok);
      if (!ok) fail(e, "<lookat> needs target != origin and up not along the view direction");
    } else {
      // Appended, not "<" + std::string(...): GCC 12's -Wrestrict false positive.
      fail(e, std::string(1, '<').append(e->Name()).append("> is not a transform step"));
    }
    m = step * m;
  }
  return m;
}

const XmlElement* named_child(const XmlElement* parent, const char* name) {
  for (const XmlElement* e = parent->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const char* n = e->Attribute("name");
    if (n && std::strcmp(n, name) == 0) return e;
  }
  return nullptr;
}

bool is(const XmlElement* e, const char* tag) { return std::strcmp(e->Name(), tag) == 0; }

}  // namespace multiray::detail
