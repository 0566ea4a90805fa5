// Mitsuba 3 scene XML (a subset; format:
// https://mitsuba.readthedocs.io/en/stable/src/key_topics/scene_format.html, plugins:
// https://mitsuba.readthedocs.io/en/stable/src/plugin_reference.html). Read:
// - <default> parameters ($name in any attribute) and <path> search folders;
// - <sensor type="perspective"> (thinlens as a pinhole): fov/fov_axis or focal_length,
//   to_world, and the film's width and height, which fix the fov conversion;
// - <bsdf type="diffuse"> (reflectance as rgb, spectrum or float), inside "twosided";
// - <emitter type="area"> inside a shape or referenced by it, and type="constant";
// - <shape> obj, ply (through load_obj/load_ply), rectangle and cube, with to_world,
//   flip_normals, and a bsdf and emitter given inline or by <ref id>.
// Other plugins (textures, other BSDFs and emitters, media, ...) give one warning per type
// and are skipped or replaced by Mitsuba's default (diffuse, reflectance 0.5). The
// integrator and sampler are render settings and come from the command line instead.
#include <tinyxml2.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "core/scene_files.h"
#include "scene/camera_check.h"
#include "scene/loaders.h"
#include "scene/mitsuba_shapes.h"
#include "scene/mitsuba_xml.h"

namespace multiray {
namespace {

namespace fs = std::filesystem;
using detail::is;
using detail::named_child;
using detail::XmlElement;

class MitsubaReader {
 public:
  MitsubaReader(const std::string& path, const LoadOptions& options)
      : files_(path, options), options_(options) {
    ctx_.path = path;
    ctx_.options = &options;
    dir_ = fs::path(path).parent_path();
    if (dir_.empty()) dir_ = ".";
  }
  Scene read();

 private:
  void read_top_level(const XmlElement* root);
  void add_sensor(const XmlElement* e);
  void add_shape(const XmlElement* e);
  void add_emitter(const XmlElement* e);
  Material material(const XmlElement* bsdf);
  const XmlElement* resolve(const XmlElement* e);  // <ref id> -> the element it names
  std::string find_file(const XmlElement* e, const std::string& name);
  float float_property(const XmlElement* e, const char* name, float fallback);

  detail::MitsubaContext ctx_;
  SceneFiles files_;
  const LoadOptions& options_;
  fs::path dir_;                  // the XML's folder
  std::vector<fs::path> search_;  // <path> folders, in document order
  std::map<std::string, const XmlElement*> ids_;
  detail::ShapeMerger merged_;
  Scene scene_;
};

Scene MitsubaReader::read() {
  const std::string text = files_.read_scene_file();
  tinyxml2::XMLDocument doc;
  if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS)
    detail::fail(ctx_.path, std::string("malformed XML: ") + doc.ErrorStr());
  const XmlElement* root = doc.RootElement();
  if (root == nullptr || !is(root, "scene"))
    detail::fail(ctx_.path, "not a Mitsuba scene (the root element is not <scene>)");
  scene_.name = detail::file_name(ctx_.path);
  read_top_level(root);
  merged_.finish(&scene_);
  detail::validate_loaded(&scene_, ctx_.path, options_);
  return std::move(scene_);
}

// Two passes: parameters, search paths and ids first, since Mitsuba lets a shape refer
// to an emitter or BSDF defined further down (its own Cornell box does).
void MitsubaReader::read_top_level(const XmlElement* root) {
  for (const XmlElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
    if (is(e, "default")) {
      ctx_.params.emplace(ctx_.attr(e, "name"), ctx_.attr(e, "value"));
    } else if (is(e, "path")) {
      search_.push_back(dir_ / ctx_.attr(e, "value"));
    } else if (e->Attribute("id")) {
      ids_[ctx_.attr(e, "id")] = e;
    }
  }
  for (const XmlElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
    if (is(e, "sensor")) {
      add_sensor(e);
    } else if (is(e, "shape")) {
      add_shape(e);
    } else if (is(e, "emitter")) {
      add_emitter(e);
    } else if (!is(e, "default") && !is(e, "path") && !is(e, "integrator") && !is(e, "bsdf") &&
               !is(e, "texture")) {  // BSDFs and textures are read where they are used
      const std::string tag = e->Name();
      ctx_.warn_once("element " + tag,
                     std::string("<").append(tag).append("> elements are not supported; skipped"));
    }
  }
}

const XmlElement* MitsubaReader::resolve(const XmlElement* e) {
  if (!is(e, "ref")) return e;
  const auto it = ids_.find(ctx_.attr(e, "id"));
  if (it == ids_.end()) ctx_.fail(e, "<ref id='" + ctx_.attr(e, "id") + "'> names nothing");
  return it->second;
}

float MitsubaReader::float_property(const XmlElement* e, const char* name, float fallback) {
  const XmlElement* p = named_child(e, name);
  return p ? float(ctx_.number(p, ctx_.attr(p, "value"))) : fallback;
}

// Mitsuba's diffuse BSDF; twosided unwrapped (our diffuse is two-sided anyway); any other
// type becomes Mitsuba's default BSDF (diffuse, reflectance 0.5) with one warning.
Material MitsubaReader::material(const XmlElement* bsdf) {
  Material m;
  m.base_color = Vec3(0.5f);
  if (bsdf == nullptr) return m;
  if (bsdf->Attribute("id")) m.name = ctx_.attr(bsdf, "id");
  const std::string type = ctx_.attr(bsdf, "type");
  if (type == "twosided") {
    for (const XmlElement* c = bsdf->FirstChildElement(); c; c = c->NextSiblingElement())
      if (is(c, "bsdf") || is(c, "ref")) return material(resolve(c));
    return m;
  }
  if (type != "diffuse") {
    ctx_.warn_once("bsdf " + type,
                   "bsdf type '" + type + "' is not supported; using diffuse grey (0.5)");
    return m;
  }
  const XmlElement* r = named_child(bsdf, "reflectance");
  if (r && (is(r, "texture") || is(r, "ref")))
    ctx_.warn_once("texture", "textured reflectance is not supported; using grey (0.5)");
  else if (r)
    m.base_color = ctx_.colour(r, /*radiance=*/false);
  return m;
}

// Mitsuba's perspective sensor looks down its local +z with +y up; its fov is measured
// along `fov_axis` of the film (default x), so it is converted to our vertical fov with
// the film's aspect ratio.
void MitsubaReader::add_sensor(const XmlElement* e) {
  const std::string type = ctx_.attr(e, "type");
  if (type != "perspective" && type != "thinlens") {
    ctx_.warn_once("sensor " + type, "sensor type '" + type + "' is not supported; skipped");
    return;
  }
  if (type == "thinlens")
    ctx_.warn_once("thinlens", "thinlens sensor read as a pinhole (no depth of field)");
  int width = 768, height = 576;  // Mitsuba's hdrfilm defaults
  if (const XmlElement* film = e->FirstChildElement("film")) {
    const float w = float_property(film, "width", float(width));
    const float h = float_property(film, "height", float(height));
    if (!(w >= 1 && h >= 1 && w <= 65536 && h <= 65536))
      ctx_.fail(film, "film width and height must be in [1, 65536]");
    width = int(w), height = int(h);
  }
  const double aspect = double(width) / double(height);
  double half_tan = 0;  // tan(fov / 2) along fov_axis
  std::string axis = "x";
  if (const XmlElement* f = named_child(e, "fov")) {
    half_tan = std::tan(0.5 * ctx_.number(f, ctx_.attr(f, "value")) * kPi / 180.0);
    if (const XmlElement* a = named_child(e, "fov_axis")) axis = ctx_.attr(a, "value");
  } else {
    // focal_length in 35 mm film terms ("50mm", the default), on the film's diagonal.
    const XmlElement* fl = named_child(e, "focal_length");
    std::string mm = fl ? ctx_.attr(fl, "value") : "50mm";
    if (mm.size() > 2 && mm.compare(mm.size() - 2, 2, "mm") == 0) mm.resize(mm.size() - 2);
    const double focal = ctx_.number(fl ? fl : e, mm);
    if (!(focal > 0)) ctx_.fail(fl ? fl : e, "focal_length must be positive");
    half_tan = std::hypot(36.0, 24.0) / (2.0 * focal);
    axis = "diagonal";
  }
  if (axis == "smaller") axis = width < height ? "x" : "y";
  if (axis == "larger") axis = width < height ? "y" : "x";
  if (axis == "x")
    half_tan /= aspect;
  else if (axis == "diagonal")
    half_tan /= std::hypot(aspect, 1.0);
  else if (axis != "y")
    ctx_.fail(e, "unknown fov_axis '" + axis + "'");
  Mat4 m;
  if (const XmlElement* t = named_child(e, "to_world")) m = ctx_.transform(t);
  Camera cam;
  cam.eye = m.point(Vec3(0, 0, 0));
  const Vec3 forward = normalize(m.vector(Vec3(0, 0, 1)));
  cam.target = cam.eye + forward * std::max(1.0f, length(cam.eye));
  cam.up = normalize(m.vector(Vec3(0, 1, 0)));
  cam.fov_y_deg = float(2.0 * std::atan(half_tan) * 180.0 / kPi);
  cam.film_width = width, cam.film_height = height;
  if (dot(cross(m.vector(Vec3(1, 0, 0)), m.vector(Vec3(0, 1, 0))), m.vector(Vec3(0, 0, 1))) < 0)
    ctx_.warn_once("mirror", "the sensor's to_world mirrors the image; rendered unmirrored");
  const std::string problem = camera_problem(cam);
  if (!problem.empty())
    ctx_.warn_once("camera",
                   "sensor at line " + std::to_string(e->GetLineNum()) + " not used: " + problem);
  else
    scene_.cameras.push_back(cam);
}

void MitsubaReader::add_emitter(const XmlElement* e) {
  const std::string type = ctx_.attr(e, "type");
  if (type == "area") {
    if (!e->Attribute("id"))
      ctx_.warn_once("lone area", "an area emitter outside a shape lights nothing; skipped");
    return;  // used by the shapes that refer to it
  }
  if (type == "constant") {
    const XmlElement* r = named_child(e, "radiance");
    scene_.environment += r ? ctx_.colour(r, /*radiance=*/true) : Vec3(1.0f);
    return;
  }
  ctx_.warn_once("emitter " + type, "emitter type '" + type + "' is not supported; skipped");
}

std::string MitsubaReader::find_file(const XmlElement* e, const std::string& name) {
  const fs::path p(name);
  if (p.is_absolute()) return name;
  // Mitsuba's resolver: the last <path> first, then the scene file's folder.
  for (auto it = search_.rbegin(); it != search_.rend(); ++it)
    if (fs::exists(*it / p)) return (*it / p).string();
  if (fs::exists(dir_ / p)) return (dir_ / p).string();
  ctx_.fail(e, "mesh file '" + name + "' not found next to the scene or in its <path> folders");
}

void MitsubaReader::add_shape(const XmlElement* e) {
  const std::string type = ctx_.attr(e, "type");
  Scene part;
  if (type == "obj" || type == "ply") {
    const XmlElement* f = named_child(e, "filename");
    if (f == nullptr) ctx_.fail(e, "<shape type='" + type + "'> needs a filename");
    const std::string file = find_file(f, ctx_.attr(f, "value"));
    std::string bytes, why;  // checked and counted like every file a scene names
    if (!files_.read(file, &bytes, &why))
      ctx_.fail(f, why +
                       " (a mesh the scene names through its <path> folders; "
                       "--allow-outside-paths reads it)");
    part = type == "obj" ? load_obj(file, options_) : load_ply(file, options_);
  } else if (type == "rectangle") {
    part = detail::mitsuba_rectangle();
  } else if (type == "cube") {
    part = detail::mitsuba_cube();
  } else {
    ctx_.warn_once("shape " + type, "shape type '" + type + "' is not supported; skipped");
    return;
  }
  const XmlElement* bsdf = nullptr;
  const XmlElement* emitter = nullptr;
  for (const XmlElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const XmlElement* r = resolve(c);
    if (is(r, "bsdf")) bsdf = r;
    if (is(r, "emitter")) emitter = r;
  }
  Material m = material(bsdf);
  if (emitter && ctx_.attr(emitter, "type") == "area") {
    const XmlElement* r = named_child(emitter, "radiance");
    if (r == nullptr) ctx_.fail(emitter, "an area emitter needs a radiance");
    m.emission = ctx_.colour(r, /*radiance=*/true);
  } else if (emitter) {
    ctx_.warn_once("shape emitter", "only area emitters can be attached to shapes");
  }
  const XmlElement* flip = named_child(e, "flip_normals");
  const bool flipped = flip && ctx_.attr(flip, "value") == "true";
  Mat4 to_world;
  if (const XmlElement* t = named_child(e, "to_world")) to_world = ctx_.transform(t);
  scene_.materials.push_back(m);
  merged_.append(part, to_world, uint32_t(scene_.materials.size() - 1), flipped);
}

}  // namespace

Scene load_mitsuba(const std::string& path, const LoadOptions& options) {
  return MitsubaReader(path, options).read();
}

}  // namespace multiray
