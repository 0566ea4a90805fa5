// Stanford PLY reader. Debian 12 packages no C/C++ PLY library (no tinyply, happly,
// rply or miniply package exists), so this is a small reader of our own covering
// what meshes use: ascii, binary_little_endian and binary_big_endian; `vertex` elements
// with x,y,z and optional nx,ny,nz and texture coordinates (u,v / s,t / texture_u,
// texture_v / texture_s,texture_t); `face` elements with a vertex_indices (or
// vertex_index) list, fan-triangulated. Every other property and element is skipped by
// its declared type. The whole file is read into memory first so that counts in the
// header can be checked against the bytes actually present before anything is
// allocated.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>

#include "scene/loaders.h"

namespace multiray {
namespace {

enum class Type { i8, u8, i16, u16, i32, u32, f32, f64 };

struct Property {
  std::string name;
  Type type = Type::f32;
  bool is_list = false;
  Type count_type = Type::u8;
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> props;
};

bool parse_type(const std::string& s, Type* t) {
  static const struct {
    const char* a;
    const char* b;
    Type t;
  } names[] = {{"char", "int8", Type::i8},      {"uchar", "uint8", Type::u8},
               {"short", "int16", Type::i16},   {"ushort", "uint16", Type::u16},
               {"int", "int32", Type::i32},     {"uint", "uint32", Type::u32},
               {"float", "float32", Type::f32}, {"double", "float64", Type::f64}};
  for (const auto& n : names)
    if (s == n.a || s == n.b) return *t = n.t, true;
  return false;
}

size_t type_size(Type t) {
  switch (t) {
    case Type::i8:
    case Type::u8:
      return 1;
    case Type::i16:
    case Type::u16:
      return 2;
    case Type::i32:
    case Type::u32:
    case Type::f32:
      return 4;
    case Type::f64:
      return 8;
  }
  return 1;
}

// Sequential reader over the body, in one of the three encodings. Every read checks
// for the end of the data; ascii reads also reject tokens that are not numbers.
class Body {
 public:
  Body(const std::string& path, const std::string& data, size_t pos, int format)
      : path_(path), data_(data), pos_(pos), format_(format) {}

  double read(Type t, const char* what) {
    return format_ == 0 ? read_ascii(t, what) : read_binary(t, what);
  }
  size_t remaining() const { return data_.size() - pos_; }
  void set_line(size_t line) { line_ = line; }

 private:
  double read_ascii(Type t, const char* what) {
    while (pos_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[pos_]))) {
      if (data_[pos_] == '\n') ++line_;
      ++pos_;
    }
    if (pos_ >= data_.size()) truncated(what);
    size_t end = pos_;
    while (end < data_.size() && !std::isspace(static_cast<unsigned char>(data_[end]))) ++end;
    const char* first = data_.data() + pos_ + (data_[pos_] == '+' ? 1 : 0);
    double v = 0;
    const auto [ptr, ec] = std::from_chars(first, data_.data() + end, v);
    const bool integral = t != Type::f32 && t != Type::f64;
    if (ec != std::errc() || ptr != data_.data() + end || (integral && v != std::floor(v)))
      detail::fail(path_, "line " + std::to_string(line_) + ": '" +
                              data_.substr(pos_, std::min<size_t>(end - pos_, 40)) + "' is not " +
                              (integral ? "an integer" : "a number") + " (reading " + what + ")");
    pos_ = end;
    return v;
  }

  double read_binary(Type t, const char* what) {
    const size_t n = type_size(t);
    if (remaining() < n) truncated(what);
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, n);
    pos_ += n;
    // The host is little-endian (x86-64, AArch64); big-endian files are swapped.
    if (format_ == 2) std::reverse(b, b + n);
    auto as = [&b](auto v) { return std::memcpy(&v, b, sizeof v), double(v); };
    switch (t) {
      case Type::i8:
        return as(int8_t());
      case Type::u8:
        return as(uint8_t());
      case Type::i16:
        return as(int16_t());
      case Type::u16:
        return as(uint16_t());
      case Type::i32:
        return as(int32_t());
      case Type::u32:
        return as(uint32_t());
      case Type::f32:
        return as(float());
      case Type::f64:
        return as(double());
    }
    return 0;
  }

  [[noreturn]] void truncated(const char* what) {
    detail::fail(path_, std::string("unexpected end of file while reading ") + what +
                            " (file truncated, or the header promises more data than present)");
  }

  const std::string& path_;
  const std::string& data_;
  size_t pos_;
  int format_;  // 0 ascii, 1 binary little-endian, 2 binary big-endian
  size_t line_ = 0;
};

}  // namespace

Scene load_ply(const std::string& path) {
  const std::string data = detail::read_file(path);
  auto fail = [&](const std::string& what) { detail::fail(path, what); };

  // --- Header: line based, ends with "end_header".
  if (data.compare(0, 3, "ply") != 0 || (data.size() > 3 && data[3] != '\n' && data[3] != '\r'))
    fail("not a PLY file (missing 'ply' magic line)");
  int format = -1;
  std::vector<Element> elements;
  size_t pos = 0, line_no = 0, body_start = std::string::npos;
  while (pos < data.size() && body_start == std::string::npos) {
    size_t eol = data.find('\n', pos);
    if (eol == std::string::npos) eol = data.size();
    std::string line = data.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ss(line);
    std::string key;
    ss >> key;
    const std::string where = "header line " + std::to_string(line_no) + ": ";
    if (key == "format") {
      std::string f;
      ss >> f;
      if (f == "ascii")
        format = 0;
      else if (f == "binary_little_endian")
        format = 1;
      else if (f == "binary_big_endian")
        format = 2;
      else
        fail(where + "unknown format '" + f + "'");
    } else if (key == "element") {
      Element e;
      std::string count;
      ss >> e.name >> count;
      const auto [p, ec] = std::from_chars(count.data(), count.data() + count.size(), e.count);
      if (e.name.empty() || ec != std::errc() || p != count.data() + count.size())
        fail(where + "malformed element line '" + line + "'");
      elements.push_back(e);
    } else if (key == "property") {
      if (elements.empty()) fail(where + "property before any element");
      Property p;
      std::string t;
      ss >> t;
      if (t == "list") {
        std::string ct, it;
        ss >> ct >> it >> p.name;
        p.is_list = true;
        if (!parse_type(ct, &p.count_type) || !parse_type(it, &p.type) || p.name.empty())
          fail(where + "malformed list property '" + line + "'");
      } else {
        ss >> p.name;
        if (!parse_type(t, &p.type) || p.name.empty())
          fail(where + "malformed property '" + line + "'");
      }
      elements.back().props.push_back(p);
    } else if (key == "end_header") {
      body_start = std::min(pos, data.size());
    }
    // "ply", "comment", "obj_info" and stray text lines (some exporters, e.g. Blender
    // 2.47 in Wuson.ply, write a comment without the keyword) are ignored.
  }
  if (body_start == std::string::npos) fail("header has no 'end_header' line");
  if (format < 0) fail("header has no 'format' line");

  // --- Plausibility of the counts before allocating: each element needs at least its
  // fixed-size bytes (binary) or one token plus separator per property (ascii).
  size_t available = data.size() - body_start;
  for (const Element& e : elements) {
    size_t min_bytes = 0;
    for (const Property& p : e.props)
      min_bytes += format == 0 ? 2 : type_size(p.is_list ? p.count_type : p.type);
    if (min_bytes > 0 && e.count > (available + 1) / min_bytes)
      fail("header promises " + std::to_string(e.count) + " '" + e.name +
           "' elements but the file has only " + std::to_string(available) +
           " bytes of data (truncated?)");
    if (e.name == "vertex" && e.count > UINT32_MAX)
      fail("too many vertices (" + std::to_string(e.count) + ")");
    available -= std::min<size_t>(available, e.count * min_bytes);
  }

  // --- Body.
  Scene scene;
  scene.name = detail::file_name(path);
  Body body(path, data, body_start, format);
  body.set_line(line_no + 1);
  bool has_normals = false, has_uvs = false;
  for (const Element& e : elements) {
    if (e.name == "vertex") {
      // Columns: 0-2 position, 3-5 normal, 6-7 uv; -1 = skipped.
      std::vector<int> column(e.props.size(), -1);
      int found = 0;
      for (size_t i = 0; i < e.props.size(); ++i) {
        static const char* names[][3] = {
            {"x", "", ""},  {"y", "", ""},  {"z", "", ""},           {"nx", "", ""},
            {"ny", "", ""}, {"nz", "", ""}, {"u", "s", "texture_u"}, {"v", "t", "texture_v"}};
        const std::string& n = e.props[i].name;
        for (int c = 0; c < 8 && !e.props[i].is_list; ++c)
          if (n == names[c][0] || n == names[c][1] || n == names[c][2] ||
              (c >= 6 && n == std::string("texture_") + names[c][1]))
            column[i] = c, found |= 1 << c;
      }
      if ((found & 7) != 7) fail("vertex element lacks one of the x, y, z properties");
      has_normals = (found & 0x38) == 0x38;
      has_uvs = (found & 0xC0) == 0xC0;
      scene.positions.resize(e.count);
      if (has_normals) scene.normals.resize(e.count);
      if (has_uvs) scene.uvs.resize(e.count);
      for (uint64_t v = 0; v < e.count; ++v) {
        float val[8] = {};
        for (size_t i = 0; i < e.props.size(); ++i) {
          const Property& p = e.props[i];
          if (p.is_list) {
            const double n = body.read(p.count_type, "a vertex property list");
            for (double k = 0; k < n; ++k) body.read(p.type, "a vertex property list");
          } else {
            const double x = body.read(p.type, "vertex data");
            if (column[i] >= 0) val[column[i]] = float(x);
          }
        }
        scene.positions[v] = Vec3(val[0], val[1], val[2]);
        if (has_normals) scene.normals[v] = normalize(Vec3(val[3], val[4], val[5]));
        // PLY texture coordinates have v = 0 at the bottom; Texture wants it at the top.
        if (has_uvs) scene.uvs[v] = Vec2{val[6], 1.0f - val[7]};
      }
    } else if (e.name == "face") {
      bool has_list = false;
      for (const Property& p : e.props)
        has_list |= p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index");
      if (!has_list) fail("face element has no vertex_indices list");
      scene.indices.reserve(scene.indices.size() + e.count * 3);
      for (uint64_t f = 0; f < e.count; ++f) {
        for (const Property& p : e.props) {
          if (!p.is_list) {
            body.read(p.type, "face data");
            continue;
          }
          const double n = body.read(p.count_type, "a face's vertex count");
          if (!(n >= 0) || n != std::floor(n))
            fail("face " + std::to_string(f) + " has a bad vertex count");
          const bool indices = p.name == "vertex_indices" || p.name == "vertex_index";
          // Fan triangulation, streamed: (first, previous, current) for each corner >= 2.
          double first = 0, prev = 0;
          for (double k = 0; k < n; ++k) {
            const double idx = body.read(p.type, "face indices");
            if (!indices) continue;
            if (!(idx >= 0 && idx < 4294967295.0) || idx != std::floor(idx))
              fail("face " + std::to_string(f) + " has an invalid vertex index " +
                   std::to_string(idx));
            if (k >= 2) {
              scene.indices.push_back(uint32_t(first));
              scene.indices.push_back(uint32_t(prev));
              scene.indices.push_back(uint32_t(idx));
            }
            (k == 0 ? first : prev) = idx;
          }
        }
      }
    } else if (!e.props.empty()) {  // (no properties: nothing to skip, whatever the count)
      for (uint64_t i = 0; i < e.count; ++i)
        for (const Property& p : e.props) {
          const double n = p.is_list ? body.read(p.count_type, "element data") : 1;
          for (double k = 0; k < n; ++k) body.read(p.type, "element data");
        }
    }
  }
  if (scene.positions.empty()) fail("no 'vertex' element with vertices");
  if (scene.indices.empty()) fail("no faces (point clouds are not supported)");
  for (size_t i = 0; i < scene.indices.size(); ++i)
    if (scene.indices[i] >= scene.positions.size())
      fail("face index " + std::to_string(scene.indices[i]) + " is out of range (" +
           std::to_string(scene.positions.size()) + " vertices)");

  scene.materials.emplace_back().name = "default";
  scene.material_ids.assign(scene.triangle_count(), 0);
  detail::validate_loaded(scene, path);
  return scene;
}

}  // namespace multiray
