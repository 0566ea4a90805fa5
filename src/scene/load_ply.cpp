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

#include "core/scene_files.h"
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

// --- Header ---------------------------------------------------------------------------

// What the header declares: the body's encoding and its elements in file order.
struct Header {
  int format = -1;  // as in Body: 0 ascii, 1 binary little-endian, 2 binary big-endian
  std::vector<Element> elements;
  size_t body_start = std::string::npos;  // offset of the first body byte
  size_t lines = 0;                       // header lines, "ply" and "end_header" included
};

// The encoding named by a "format" line (0, 1 or 2 as in Header), or -1 if unknown.
int parse_format(const std::string& f) {
  if (f == "ascii") return 0;
  if (f == "binary_little_endian") return 1;
  if (f == "binary_big_endian") return 2;
  return -1;
}

// Reads the rest of an "element <name> <count>" line into `e`. Returns false when the
// name is missing or the count is not a plain unsigned integer.
bool parse_element(std::istringstream& ss, Element* e) {
  std::string count;
  ss >> e->name >> count;
  const auto [p, ec] = std::from_chars(count.data(), count.data() + count.size(), e->count);
  return !e->name.empty() && ec == std::errc() && p == count.data() + count.size();
}

// Reads the rest of a "property <type> <name>" or "property list <count type> <item
// type> <name>" line into `p`. Returns false when a type is unknown or the name missing;
// `p->is_list` then tells which of the two forms was meant.
bool parse_property(std::istringstream& ss, Property* p) {
  std::string t;
  ss >> t;
  if (t != "list") {
    ss >> p->name;
    return parse_type(t, &p->type) && !p->name.empty();
  }
  std::string ct, it;
  ss >> ct >> it >> p->name;
  p->is_list = true;
  return parse_type(ct, &p->count_type) && parse_type(it, &p->type) && !p->name.empty();
}

// Applies one header line (without its line break) to `h`, whose `lines` already counts
// it. Returns true for "end_header". "ply", "comment", "obj_info" and stray text lines
// (some exporters, e.g. Blender 2.47 in Wuson.ply, write a comment without the keyword)
// are ignored. Fails on an unknown format and on malformed element or property lines.
bool parse_header_line(const std::string& path, const std::string& line, Header* h) {
  std::istringstream ss(line);
  std::string key;
  ss >> key;
  const std::string where = "header line " + std::to_string(h->lines) + ": ";
  if (key == "format") {
    std::string f;
    ss >> f;
    h->format = parse_format(f);
    if (h->format < 0) detail::fail(path, where + "unknown format '" + f + "'");
  } else if (key == "element") {
    Element e;
    if (!parse_element(ss, &e))
      detail::fail(path, where + "malformed element line '" + line + "'");
    h->elements.push_back(e);
  } else if (key == "property") {
    if (h->elements.empty()) detail::fail(path, where + "property before any element");
    Property p;
    if (!parse_property(ss, &p)) {
      const char* form = p.is_list ? "malformed list property '" : "malformed property '";
      detail::fail(path, where + form + line + "'");
    }
    h->elements.back().props.push_back(p);
  }
  return key == "end_header";
}

// Parses the line-based header at the start of `data`, which ends with an "end_header"
// line. Fails without the "ply" magic line, without an "end_header" or "format" line,
// and on any line parse_header_line rejects.
Header parse_header(const std::string& path, const std::string& data) {
  if (data.compare(0, 3, "ply") != 0 || (data.size() > 3 && data[3] != '\n' && data[3] != '\r'))
    detail::fail(path, "not a PLY file (missing 'ply' magic line)");
  Header h;
  size_t pos = 0;
  while (pos < data.size() && h.body_start == std::string::npos) {
    size_t eol = data.find('\n', pos);
    if (eol == std::string::npos) eol = data.size();
    std::string line = data.substr(pos, eol - pos);
    pos = eol + 1;
    ++h.lines;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (parse_header_line(path, line, &h)) h.body_start = std::min(pos, data.size());
  }
  if (h.body_start == std::string::npos) detail::fail(path, "header has no 'end_header' line");
  if (h.format < 0) detail::fail(path, "header has no 'format' line");
  return h;
}

// Fails, before anything is allocated, when the header promises more elements than the
// `data_size` bytes of the file can hold: each element needs at least its fixed-size
// bytes (binary) or one token plus separator per property (ascii). Also refuses more
// vertices than a 32-bit index can address.
void check_counts(const std::string& path, const Header& h, size_t data_size) {
  size_t available = data_size - h.body_start;
  for (const Element& e : h.elements) {
    size_t min_bytes = 0;
    for (const Property& p : e.props)
      min_bytes += h.format == 0 ? 2 : type_size(p.is_list ? p.count_type : p.type);
    if (min_bytes > 0 && e.count > (available + 1) / min_bytes)
      detail::fail(path, "header promises " + std::to_string(e.count) + " '" + e.name +
                             "' elements but the file has only " + std::to_string(available) +
                             " bytes of data (truncated?)");
    if (e.name == "vertex" && e.count > UINT32_MAX)
      detail::fail(path, "too many vertices (" + std::to_string(e.count) + ")");
    available -= std::min<size_t>(available, e.count * min_bytes);
  }
}

// --- Body -----------------------------------------------------------------------------

// Where each property of a vertex element goes: 0-2 position, 3-5 normal, 6-7 uv, or
// -1 (skipped: list properties and other names). Sets bit c of *found for each column c
// that some property fills.
std::vector<int> vertex_columns(const Element& e, int* found) {
  static const char* names[][3] = {{"x", "", ""},           {"y", "", ""},          {"z", "", ""},
                                   {"nx", "", ""},          {"ny", "", ""},         {"nz", "", ""},
                                   {"u", "s", "texture_u"}, {"v", "t", "texture_v"}};
  std::vector<int> column(e.props.size(), -1);
  *found = 0;
  for (size_t i = 0; i < e.props.size(); ++i) {
    const std::string& n = e.props[i].name;
    for (int c = 0; c < 8 && !e.props[i].is_list; ++c)
      if (n == names[c][0] || n == names[c][1] || n == names[c][2] ||
          (c >= 6 && n == std::string("texture_") + names[c][1]))
        column[i] = c, *found |= 1 << c;
  }
  return column;
}

// Reads the `e.count` vertices of vertex element `e` into scene->positions (resized to
// `e.count`), and into scene->normals (normalised) and scene->uvs (v flipped) when the
// element has all their components (unusable normals are NaN until validate_loaded()
// repairs them). Fails when x, y or z is missing.
void read_vertices(const std::string& path, const Element& e, Body* body, Scene* scene) {
  int found = 0;
  const std::vector<int> column = vertex_columns(e, &found);
  if ((found & 7) != 7) detail::fail(path, "vertex element lacks one of the x, y, z properties");
  const bool has_normals = (found & 0x38) == 0x38;
  const bool has_uvs = (found & 0xC0) == 0xC0;
  scene->positions.resize(e.count);
  if (has_normals) scene->normals.resize(e.count);
  if (has_uvs) scene->uvs.resize(e.count);
  for (uint64_t v = 0; v < e.count; ++v) {
    float val[8] = {};
    for (size_t i = 0; i < e.props.size(); ++i) {
      const Property& p = e.props[i];
      if (p.is_list) {
        const double n = body->read(p.count_type, "a vertex property list");
        for (double k = 0; k < n; ++k) body->read(p.type, "a vertex property list");
      } else {
        const double x = body->read(p.type, "vertex data");
        if (column[i] >= 0) val[column[i]] = detail::to_float(x);
      }
    }
    scene->positions[v] = Vec3(val[0], val[1], val[2]);
    if (has_normals) scene->normals[v] = detail::shading_normal(Vec3(val[3], val[4], val[5]));
    // PLY texture coordinates have v = 0 at the bottom; Texture wants it at the top.
    if (has_uvs) scene->uvs[v] = Vec2{val[6], 1.0f - val[7]};
  }
}

// The list holding a face's vertex indices, under either of its customary names.
bool is_vertex_index_list(const Property& p) {
  return p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index");
}

// Reads list property `p` of face number `face`. For the vertex index list, appends its
// fan triangulation to *indices; other lists are read and dropped. Fails on a vertex
// count that is not a non-negative integer and on an index that is not a 32-bit one
// (whether it is in range is checked once all vertices are known).
void read_face_list(const std::string& path, uint64_t face, const Property& p, Body* body,
                    std::vector<uint32_t>* indices) {
  const double n = body->read(p.count_type, "a face's vertex count");
  if (!(n >= 0) || n != std::floor(n))
    detail::fail(path, "face " + std::to_string(face) + " has a bad vertex count");
  const bool keep = is_vertex_index_list(p);
  // Fan triangulation, streamed: (first, previous, current) for each corner >= 2.
  double first = 0, prev = 0;
  for (double k = 0; k < n; ++k) {
    const double idx = body->read(p.type, "face indices");
    if (!keep) continue;
    if (!(idx >= 0 && idx < 4294967295.0) || idx != std::floor(idx))
      detail::fail(path, "face " + std::to_string(face) + " has an invalid vertex index " +
                             std::to_string(idx));
    if (k >= 2) {
      indices->push_back(uint32_t(first));
      indices->push_back(uint32_t(prev));
      indices->push_back(uint32_t(idx));
    }
    (k == 0 ? first : prev) = idx;
  }
}

// Reads the `e.count` faces of face element `e`, appending their triangles to
// *indices. Fails when the element has no vertex_indices (or vertex_index) list.
void read_faces(const std::string& path, const Element& e, Body* body,
                std::vector<uint32_t>* indices) {
  if (std::none_of(e.props.begin(), e.props.end(), is_vertex_index_list))
    detail::fail(path, "face element has no vertex_indices list");
  indices->reserve(indices->size() + e.count * 3);
  for (uint64_t f = 0; f < e.count; ++f)
    for (const Property& p : e.props) {
      if (p.is_list)
        read_face_list(path, f, p, body, indices);
      else
        body->read(p.type, "face data");
    }
}

// Reads past the `e.count` instances of an element the scene does not use.
void skip_element(const Element& e, Body* body) {
  if (e.props.empty()) return;  // nothing to skip, whatever the count
  for (uint64_t i = 0; i < e.count; ++i)
    for (const Property& p : e.props) {
      const double n = p.is_list ? body->read(p.count_type, "element data") : 1;
      for (double k = 0; k < n; ++k) body->read(p.type, "element data");
    }
}

// Completes the scene read from the body: requires vertices and faces, checks every
// index against the vertex count, gives all triangles one default material, and
// validates the result as every loader does.
void build_mesh(const std::string& path, const LoadOptions& options, Scene* scene) {
  if (scene->positions.empty()) detail::fail(path, "no 'vertex' element with vertices");
  if (scene->indices.empty()) detail::fail(path, "no faces (point clouds are not supported)");
  for (const uint32_t index : scene->indices)
    if (index >= scene->positions.size())
      detail::fail(path, "face index " + std::to_string(index) + " is out of range (" +
                             std::to_string(scene->positions.size()) + " vertices)");
  scene->materials.emplace_back().name = "default";
  scene->material_ids.assign(scene->triangle_count(), 0);
  detail::validate_loaded(scene, path, options);
}

}  // namespace

Scene load_ply(const std::string& path, const LoadOptions& options) {
  const std::string data = SceneFiles(path, options).read_scene_file();
  const Header header = parse_header(path, data);
  check_counts(path, header, data.size());

  // Elements in file order: the body has no index, so unused ones are read past.
  Scene scene;
  scene.name = detail::file_name(path);
  Body body(path, data, header.body_start, header.format);
  body.set_line(header.lines + 1);
  for (const Element& e : header.elements) {
    if (e.name == "vertex")
      read_vertices(path, e, &body, &scene);
    else if (e.name == "face")
      read_faces(path, e, &body, &scene.indices);
    else
      skip_element(e, &body);
  }
  build_mesh(path, options, &scene);
  return scene;
}

}  // namespace multiray
