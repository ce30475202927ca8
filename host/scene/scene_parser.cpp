// The scene schema: each table's keys, defaults and ranges, read through TableReader.
#include "host/scene/scene_parser.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "host/engine/sim_config.h"
#include "host/scene/named_materials.h"
#include "host/scene/toml_reader.h"
#include "host/scene/toml_writer.h"
#include "kernels/core/error.h"
#include "kernels/math/rotation.h"
#include "kernels/mpm/input_schedule.h"
#include "nn/io/snapshot_layout.h"
#include "nn/nclaw/law_file_format.h"

namespace romp::scene {
namespace {

namespace fs = std::filesystem;
using material::MaterialModel;

constexpr double kPi = 3.14159265358979323846;
// A ratio that must be a whole number (domain size / dx, end time × frame rate) may miss it by this
// much relative to itself, which absorbs decimal literals such as 0.3 / 0.1.
constexpr double kWholeTolerance = 1e-6;
// The largest scene file read: far beyond a hand-written or generated scene (meshes are files of their own).
constexpr std::uintmax_t kMaxSceneBytes = std::uintmax_t(8) << 20;

struct SceneReader {
  ReadContext context;
  fs::path folder;
  Scene scene;
};

// A rotation given as an axis and an angle in degrees.
Mat3<double> read_rotation(TableReader& t) {
  const Vec3<double> axis = t.vec3("rotation_axis", Vec3<double>(0.0, 0.0, 1.0));
  const double degrees = t.number("rotation_degrees", 0.0, Range::closed(-360.0, 360.0));
  const double length = norm(axis);
  if (!(length > 0.0)) t.fail("rotation_axis", "must be a non-zero vector");
  return rotation_from_vector(axis * (degrees * kPi / 180.0 / length));
}

Vec3<double> read_unit(TableReader& t, const std::string& key, const Vec3<double>& fallback) {
  const Vec3<double> v = t.vec3(key, fallback);
  const double length = norm(v);
  if (!(length > 0.0)) t.fail(key, "must be a non-zero vector");
  return v * (1.0 / length);
}

Vec3<double> read_positive_vec3(TableReader& t, const std::string& key) {
  const Vec3<double> v = t.required_vec3(key);
  for (int a = 0; a < 3; ++a)
    if (!(v[a] > 0.0)) t.fail(key, fmt::format("every entry must be > 0, got {}", v[a]));
  return v;
}

// The rotation taking local y to the unit vector `to` (the smallest such rotation).
Mat3<double> rotation_from_y(const Vec3<double>& to) {
  const Vec3<double> y(0.0, 1.0, 0.0);
  const Vec3<double> axis = cross(y, to);
  const double s = norm(axis), c = dot(y, to);
  if (s < 1e-12) return c > 0.0 ? Mat3<double>::identity() : Mat3<double>::diag(1.0, -1.0, -1.0);
  return rotation_from_vector(axis * (std::atan2(s, c) / s));
}

// The absolute path of the existing file that `key` names (relative to the scene's folder unless
// absolute), which must end in one of `extensions`; `what` names it in errors. The resolved scene
// records the absolute path.
std::string read_input_file(TableReader& t, const std::string& key, const fs::path& folder, const std::string& what,
                            const std::vector<std::string>& extensions) {
  const std::string file = t.required_string(key);
  const fs::path path = fs::path(file).is_absolute() ? fs::path(file) : folder / file;
  std::error_code error;
  const fs::path absolute = fs::weakly_canonical(path, error);
  if (error || !fs::is_regular_file(absolute)) t.fail(key, fmt::format("no {} file at {}", what, path.string()));
  const std::string extension = absolute.extension().string();
  if (std::find(extensions.begin(), extensions.end(), extension) == extensions.end())
    t.fail(key, fmt::format("a {} file must end in {}", what, fmt::join(extensions, " or ")));
  t.resolve_as(key, absolute.string());
  return absolute.string();
}

ShapeSpec read_shape(TableReader t, const std::vector<std::string>& types, const fs::path& folder) {
  ShapeSpec shape;
  const std::string type = t.required_choice("type", types);
  if (type == "box") {
    shape.type = ShapeType::Box;
    shape.center = t.required_vec3("center");
    shape.size = read_positive_vec3(t, "size");
    shape.rotation = read_rotation(t);
  } else if (type == "sphere") {
    shape.type = ShapeType::Sphere;
    shape.center = t.required_vec3("center");
    shape.radius = t.required_number("radius", Range::positive());
  } else if (type == "cylinder") {
    shape.type = ShapeType::Cylinder;
    shape.center = t.required_vec3("center");
    shape.radius = t.required_number("radius", Range::positive());
    shape.height = t.required_number("height", Range::positive());
    shape.axis = read_unit(t, "axis", Vec3<double>(0.0, 1.0, 0.0));
  } else if (type == "capsule") {
    shape.type = ShapeType::Capsule;
    shape.a = t.required_vec3("a");
    shape.b = t.required_vec3("b");
    shape.radius = t.required_number("radius", Range::positive());
  } else {
    shape.type = ShapeType::Mesh;
    shape.mesh_file = read_input_file(t, "file", folder, "mesh", {".obj", ".ply"});
    shape.center = t.required_vec3("center");
    shape.mesh_extent = t.required_number("extent", Range::positive());
    shape.rotation = read_rotation(t);
  }
  t.finish();
  return shape;
}

Vec3<double> shape_center(const ShapeSpec& shape) {
  return shape.type == ShapeType::Capsule ? (shape.a + shape.b) * 0.5 : shape.center;
}

// Whether `name` holds a control character (a byte below 0x20, or DEL): names reach terminals and logs,
// where such a byte would act rather than show.
bool has_control_character(const std::string& name) {
  return std::any_of(name.begin(), name.end(),
                     [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; });
}

void read_scene_table(SceneReader& r, TableReader t, const std::string& file) {
  r.scene.name = t.string("name", fs::path(file).stem().string());
  if (r.scene.name.empty() || r.scene.name.find_first_of("/\\") != std::string::npos ||
      has_control_character(r.scene.name))
    t.fail("name", "must be a non-empty name without slashes or control characters (it names the output files)");
  r.scene.description = t.string("description", "");
  r.scene.mode = t.choice("mode", "full-order", {"full-order"});
  t.finish();
}

std::int32_t whole_ratio(TableReader& t, const std::string& key, double ratio, const std::string& what) {
  constexpr double kMost = double(std::numeric_limits<std::int32_t>::max());
  const double rounded = std::round(ratio);
  if (rounded < 1.0 || std::fabs(ratio - rounded) > kWholeTolerance * rounded)
    t.fail(key, fmt::format("{} is {:.9g}; it must be a whole number >= 1", what, ratio));
  // Checked before the conversion, which past int32's range is undefined (it gave -2147483648 frames).
  if (rounded > kMost) t.fail(key, fmt::format("{} is {:.9g}; it must be at most {:.0f}", what, ratio, kMost));
  return std::int32_t(rounded);
}

void read_domain(SceneReader& r, TableReader t) {
  Scene& s = r.scene;
  s.domain_size = read_positive_vec3(t, "size");
  s.dx = t.required_number("dx", Range::positive());
  for (int a = 0; a < 3; ++a) {
    s.domain_cells[a] = whole_ratio(t, "size", s.domain_size[a] / s.dx, fmt::format("size[{}] / dx", a));
    if (s.domain_cells[a] > 1 << 20) t.fail("dx", "the domain would span more than 2^20 cells along an axis");
  }
  t.finish();
}

void read_time(SceneReader& r, TableReader t) {
  Scene& s = r.scene;
  s.end_time = t.required_number("end", Range::positive());
  s.frame_rate = t.number("frame_rate", 30.0, Range::open_closed(0.0, 1e7));
  s.frame_count = whole_ratio(t, "frame_rate", s.end_time * s.frame_rate, "end × frame_rate (the frame count)");
  // The engine steps in float: a step below float's smallest normal number would round to 0 there, which
  // means "no fixed step" (dt) or no step at all (max_dt).
  const Range step_range = Range::closed(double(std::numeric_limits<float>::min()), 1.0);
  if (t.has("dt")) {
    s.fixed_dt = t.number("dt", 0.0, step_range);
  } else {
    // The implicit step is stable beyond the explicit limit ([solver] is read first).
    const double most_cfl = s.integrator == "implicit" ? double(engine::kImplicitMaxCfl) : 1.0;
    s.cfl = t.number("cfl", 0.5, Range::open_closed(0.0, most_cfl));
    s.max_dt = t.number("max_dt", 1e-3, step_range);
  }
  t.finish();
}

mpm::ContactType read_contact(TableReader& t, const std::string& fallback) {
  const std::string contact = t.choice("contact", fallback, {"sticky", "slip", "separate"});
  return contact == "sticky" ? mpm::ContactType::Sticky
         : contact == "slip" ? mpm::ContactType::Slip
                             : mpm::ContactType::Separate;
}

void read_solver(SceneReader& r, TableReader t) {
  r.scene.transfer = t.choice("transfer", "apic", {"apic", "pic-flip"});
  if (r.scene.transfer == "pic-flip") r.scene.flip_alpha = t.number("flip_alpha", 0.95, Range::closed(0.0, 1.0));
  r.scene.enrichment = t.number("enrichment", 0.6, Range::closed_open(0.0, 1.0));
  r.scene.integrator = t.choice("integrator", "explicit", {"explicit", "implicit"});
  t.finish();
}

void read_boundary(SceneReader& r, TableReader t) {
  Scene& s = r.scene;
  const std::int32_t smallest = std::min({s.domain_cells[0], s.domain_cells[1], s.domain_cells[2]});
  // FullOrderSim needs interior cells between the walls: cells > 2 (wall_cells + 1).
  const double most = std::max(0.0, std::ceil(double(smallest) / 2.0) - 2.0);
  s.wall_cells =
      std::int32_t(t.integer("wall_cells", std::min<std::int64_t>(3, std::int64_t(most)), Range::closed(0.0, most)));
  s.wall_contact = read_contact(t, "separate");
  if (s.wall_contact != mpm::ContactType::Sticky) s.wall_friction = t.number("friction", 0.0, Range::non_negative());
  t.finish();
}

MaterialSpecification read_material(TableReader t, const std::string& name, const fs::path& folder) {
  MaterialSpecification m;
  if (t.has("neural")) {
    // A learned law (romp learn-law) brings its own stress and plasticity; only the density is the scene's.
    m.name = name;
    m.model = MaterialModel::Neural;
    m.neural_law = read_input_file(t, "neural", folder, "neural law", {".h5"});
    m.density = t.number("density", m.density, Range::positive());
    m.neural_law_source = t.located("neural");
    t.finish();
    // That it is a law file of a version this romp reads; its networks are loaded and checked where the
    // run is set up (to_material_spec), so that parsing (`romp check`) runs no network.
    try {
      io::open_versioned_file(m.neural_law, nn::nclaw::kLawFile);
    } catch (const Error& error) {
      t.fail("neural", error.what());
    }
    return m;
  }
  const std::string preset = t.choice("preset", "none", {"none", "jelly", "sand", "plasticine", "water"});
  if (preset != "none") m = scene::nclaw_preset(*scene::nclaw_material_named(preset));
  static const std::vector<std::pair<std::string, MaterialModel>> kModels = {
      {"fixed-corotated", MaterialModel::FixedCorotated}, {"neo-hookean", MaterialModel::NeoHookean},
      {"hencky-stvk", MaterialModel::HenckyStVK},         {"von-mises", MaterialModel::VonMises},
      {"drucker-prager", MaterialModel::DruckerPrager},   {"fluid", MaterialModel::WeaklyCompressibleFluid}};
  std::vector<std::string> names;
  std::string current;
  for (const auto& [model_name, model] : kModels) {
    names.push_back(model_name);
    if (model == m.model) current = model_name;
  }
  const std::string model = preset == "none" ? t.required_choice("model", names) : t.choice("model", current, names);
  for (const auto& [model_name, value] : kModels)
    if (model_name == model) m.model = value;
  m.name = name;
  m.density = t.number("density", m.density, Range::positive());
  m.youngs_modulus = t.number("youngs_modulus", m.youngs_modulus, Range::positive());
  m.poissons_ratio = t.number("poissons_ratio", m.poissons_ratio, Range::open_closed(-1.0, 0.49999));
  if (m.model == MaterialModel::VonMises) m.yield_stress = t.number("yield_stress", m.yield_stress, Range::positive());
  if (m.model == MaterialModel::DruckerPrager) {
    m.friction_angle = t.number("friction_angle", m.friction_angle, Range::closed_open(0.0, 90.0));
    m.cohesion = t.number("cohesion", m.cohesion, Range::non_negative());
  }
  if (m.model != MaterialModel::WeaklyCompressibleFluid)
    m.min_stretch = t.number("min_stretch", m.min_stretch, Range::closed_open(0.0, 1.0));
  if (t.has("strength_off")) {
    if (m.model != MaterialModel::FixedCorotated && m.model != MaterialModel::NeoHookean &&
        m.model != MaterialModel::HenckyStVK)
      t.fail("strength_off",
             "only the hyperelastic models (fixed-corotated, neo-hookean, hencky-stvk) can lose their strength");
    const std::vector<double> window = t.numbers("strength_off", {}, Range::non_negative(), 2, 2);
    if (!(window[1] > window[0]))
      t.fail("strength_off", fmt::format("[from, until] must have until > from, got [{}, {}]", window[0], window[1]));
    m.strength_off_from = window[0];
    m.strength_off_until = window[1];
  }
  t.finish();
  return m;
}

void read_materials(SceneReader& r, TableReader t) {
  for (const std::string& name : t.keys()) r.scene.materials.push_back(read_material(t.table(name), name, r.folder));
  if (r.scene.materials.empty()) t.fail("", "a scene needs at least one material, e.g. [materials.jelly]");
  t.finish();
}

std::int32_t material_index(SceneReader& r, TableReader& t) {
  const auto& materials = r.scene.materials;
  std::vector<std::string> names;
  for (const MaterialSpecification& m : materials) names.push_back(m.name);
  const std::string name =
      materials.size() == 1 ? t.choice("material", names[0], names) : t.required_choice("material", names);
  return std::int32_t(std::find(names.begin(), names.end(), name) - names.begin());
}

SamplingSpec read_sampling(TableReader t) {
  SamplingSpec sampling;
  const std::string method = t.choice("method", "lattice", {"lattice", "jittered", "poisson"});
  sampling.method = method == "lattice"    ? SamplingMethod::Lattice
                    : method == "jittered" ? SamplingMethod::JitteredLattice
                                           : SamplingMethod::PoissonDisk;
  sampling.per_cell = std::int32_t(t.integer("per_cell", 2, Range::closed(1, 16)));
  if (sampling.method == SamplingMethod::JitteredLattice)
    sampling.jitter = t.number("jitter", 1.0, Range::closed(0, 1));
  if (sampling.method != SamplingMethod::Lattice)
    sampling.seed = std::uint64_t(t.integer("seed", 0, Range::closed(0, 9e15)));
  t.finish();
  return sampling;
}

void read_objects(SceneReader& r, TableReader& root) {
  std::vector<TableReader> objects = root.tables("objects");
  if (objects.empty()) root.fail("objects", "a scene needs at least one [[objects]] entry");
  for (std::size_t i = 0; i < objects.size(); ++i) {
    TableReader& t = objects[i];
    ObjectSpec object;
    object.name = t.string("name", fmt::format("object{}", i));
    if (has_control_character(object.name)) t.fail("name", "must not hold control characters (it is printed)");
    object.material = material_index(r, t);
    if (t.has("points")) {
      // A point file replaces the shape and its sampling; its velocities (if any) add to `velocity`.
      for (const char* key : {"shape", "sampling", "domains"})
        if (t.has(key)) t.fail(key, "an object read from `points` has no shape, sampling or domains");
      object.points_file = read_input_file(t, "points", r.folder, "point", {".ply", ".h5"});
      const bool snapshot = fs::path(object.points_file).extension() == ".h5";
      object.points_frame = snapshot ? t.integer("points_frame", 0, Range::closed(0, 999999)) : 0;
      // A PLY file may give each point its volume; a snapshot always does.
      if (!snapshot) object.particle_volume = t.number("particle_volume", 0.0, Range::non_negative());
    } else {
      object.shape = read_shape(t.table("shape"), {"box", "sphere", "cylinder", "capsule", "mesh"}, r.folder);
      object.sampling = read_sampling(t.optional_table("sampling"));
    }
    const TableReader::VectorField velocity = t.vec3_field("velocity", {"x", "y", "z"});
    object.velocity = velocity.constant;
    object.velocity_formulas = velocity.formulas;
    object.angular_velocity = t.vec3("angular_velocity", Vec3<double>::zero());
    object.domains = t.boolean("domains", false);
    if (object.domains && object.sampling.method != SamplingMethod::Lattice)
      t.fail("domains", "particle domains are the cells of the sampling lattice: use sampling.method = \"lattice\"");
    t.finish();
    r.scene.objects.push_back(std::move(object));
  }
}

// The engine computes a substep's colliders, pokes and tractions on the device from masks of which act
// (mpm::kMostScheduledInputs bits).
std::vector<TableReader> scheduled_tables(TableReader& parent, const std::string& key) {
  std::vector<TableReader> tables = parent.tables(key);
  if (tables.size() > std::size_t(mpm::kMostScheduledInputs))
    parent.fail(key, fmt::format("at most {} entries, got {}", mpm::kMostScheduledInputs, tables.size()));
  return tables;
}

void read_colliders(SceneReader& r, TableReader& root) {
  for (TableReader& t : scheduled_tables(root, "colliders")) {
    ColliderSpecification c;
    const std::string type = t.required_choice("type", {"plane", "box", "sphere", "cylinder"});
    if (type == "plane") {
      c.shape = mpm::ColliderShape::HalfSpace;
      c.center = t.required_vec3("point");
      c.rotation = rotation_from_y(read_unit(t, "normal", Vec3<double>(0.0, 1.0, 0.0)));
    } else if (type == "box") {
      c.shape = mpm::ColliderShape::Box;
      c.center = t.required_vec3("center");
      c.half_extents = read_positive_vec3(t, "size") * 0.5;
      c.rotation = read_rotation(t);
    } else if (type == "sphere") {
      c.shape = mpm::ColliderShape::Sphere;
      c.center = t.required_vec3("center");
      c.half_extents = Vec3<double>::constant(t.required_number("radius", Range::positive()));
    } else {
      c.shape = mpm::ColliderShape::Cylinder;
      c.center = t.required_vec3("center");
      const double radius = t.required_number("radius", Range::positive());
      const double height = t.required_number("height", Range::positive());
      c.half_extents = Vec3<double>(radius, 0.5 * height, radius);
      c.rotation = rotation_from_y(read_unit(t, "axis", Vec3<double>(0.0, 1.0, 0.0)));
    }
    c.contact = read_contact(t, "sticky");
    if (c.contact != mpm::ContactType::Sticky) c.friction = t.number("friction", 0.0, Range::non_negative());
    c.velocity = t.vec3("velocity", Vec3<double>::zero());
    c.angular_velocity = t.vec3("angular_velocity", Vec3<double>::zero());
    if (t.has("end")) c.end = t.number("end", 0.0, Range::positive());
    t.finish();
    r.scene.colliders.push_back(c);
  }
}

void read_dirichlet(SceneReader& r, TableReader& root) {
  std::vector<TableReader> groups = root.tables("dirichlet");
  for (std::size_t i = 0; i < groups.size(); ++i) {
    TableReader& t = groups[i];
    DirichletGroupSpec group;
    group.name = t.string("name", fmt::format("group{}", i));
    group.region = read_shape(t.table("region"), {"box", "sphere", "cylinder", "capsule"}, r.folder);
    group.velocity = t.vec3("velocity", Vec3<double>::zero());
    group.angular_velocity = t.vec3("angular_velocity", Vec3<double>::zero());
    group.pivot = t.vec3("pivot", shape_center(group.region));
    if (t.has("end")) group.end = t.number("end", 0.0, Range::positive());
    t.finish();
    r.scene.dirichlet.push_back(std::move(group));
  }
}

// A region of a poke or a domain release: a sphere or an axis-aligned box.
ShapeSpec read_region(SceneReader& r, TableReader& t, const std::string& what) {
  ShapeSpec region = read_shape(t.table("region"), {"box", "sphere"}, r.folder);
  if (region.type == ShapeType::Box && !(region.rotation == Mat3<double>::identity()))
    t.fail("region", "a " + what + "'s box must be axis-aligned (rotation_degrees = 0)");
  return region;
}

void read_domain_releases(SceneReader& r, TableReader& root) {
  for (TableReader& t : root.tables("domain_release")) {
    const bool any_domains =
        std::any_of(r.scene.objects.begin(), r.scene.objects.end(), [](const ObjectSpec& o) { return o.domains; });
    if (!any_domains) t.fail("", "releases particle domains, but no object has domains = true");
    DomainReleaseSpecification release;
    release.region = read_region(r, t, "domain release");
    release.start = t.number("start", 0.0, Range::non_negative());
    if (t.has("end")) release.end = t.number("end", 0.0, Range::positive());
    if (!(release.end > release.start)) t.fail("end", fmt::format("must be > start = {}", release.start));
    t.finish();
    r.scene.domain_releases.push_back(std::move(release));
  }
}

void read_loads(SceneReader& r, TableReader t) {
  r.scene.gravity = t.vec3("gravity", Vec3<double>(0.0, -9.81, 0.0));
  for (TableReader& p : scheduled_tables(t, "pokes")) {
    PokeSpec poke;
    poke.region = read_region(r, p, "poke");
    poke.acceleration = p.required_vec3("acceleration");
    poke.start = p.number("start", 0.0, Range::non_negative());
    poke.end = p.required_number("end", Range::positive());
    if (!(poke.end > poke.start)) p.fail("end", fmt::format("must be > start = {}", poke.start));
    p.finish();
    r.scene.pokes.push_back(std::move(poke));
  }
  const std::vector<TableReader> tractions = scheduled_tables(t, "tractions");
  for (std::size_t i = 0; i < tractions.size(); ++i) {
    TableReader p = tractions[i];
    TractionSpecification traction;
    traction.name = p.string("name", fmt::format("traction{}", i));
    if (has_control_character(traction.name)) p.fail("name", "must not hold control characters (it is printed)");
    traction.region = read_shape(p.table("region"), {"box", "sphere", "cylinder", "capsule"}, r.folder);
    traction.traction = p.required_vec3("traction");
    traction.start = p.number("start", 0.0, Range::non_negative());
    if (p.has("end")) traction.end = p.number("end", 0.0, Range::positive());
    if (!(traction.end > traction.start)) p.fail("end", fmt::format("must be > start = {}", traction.start));
    p.finish();
    r.scene.tractions.push_back(std::move(traction));
  }
  t.finish();
}

void read_output(SceneReader& r, TableReader t) {
  OutputSpec& o = r.scene.output;
  o.file = t.string("file", "runs/" + r.scene.name + ".h5");
  if (fs::path(o.file).extension() != ".h5") t.fail("file", "the snapshot file name must end in .h5");
  o.fields = t.choices("fields", {"x", "v", "F", "C"}, io::field_names(io::kAllFields));
  if (std::find(o.fields.begin(), o.fields.end(), "x") == o.fields.end())
    t.fail("fields", "must include \"x\" (positions place every other field)");
  o.ply = t.boolean("ply", false);
  t.finish();
}

ParameterValues read_parameters(SceneReader& r, TableReader t, const ParameterValues& overrides) {
  ParameterValues values;
  for (const std::string& name : t.keys()) {
    if (name == "pi") t.fail(name, "'pi' is a constant and cannot be a parameter name");
    values[name] = t.number(name, 0.0, Range::any());
  }
  for (const auto& [name, value] : overrides) {
    if (!values.count(name)) t.fail("", fmt::format("sets undeclared parameter '{}'", name));
    values[name] = value;
  }
  t.finish();
  r.scene.parameters = std::map<std::string, double>(values.begin(), values.end());
  return values;
}

// `document` with each of `laws`' materials replaced by a neural one (parse_scene).
toml::table with_learned_laws(toml::table document, const std::string& file, const LearnedLaws& laws) {
  toml::table* materials = document["materials"].as_table();
  for (const auto& [name, law] : laws) {
    toml::table* material = materials ? (*materials)[name].as_table() : nullptr;
    if (!material) {
      std::vector<std::string> names;
      if (materials)
        for (const auto& entry : *materials) names.emplace_back(entry.first.str());
      throw SceneError(fmt::format("{}: a learned law replaces material '{}', which the scene lacks (it has: {})", file,
                                   name, fmt::join(names, ", ")));
    }
    toml::table learned;
    learned.insert("neural", fs::absolute(law).string());
    if (const toml::node* density = material->get("density")) learned.insert("density", *density);
    materials->insert_or_assign(name, std::move(learned));
  }
  return document;
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& file, const ParameterValues& overrides,
                  const LearnedLaws& laws) {
  const toml::table document = with_learned_laws(parse_toml(text, file), file, laws);
  SceneReader r;
  r.context.file = file;
  r.folder = fs::absolute(fs::path(file)).parent_path();
  toml::table resolved;
  TableReader root(document, resolved, "", r.context);

  r.context.parameters = read_parameters(r, root.optional_table("parameters"), overrides);
  // The resolved [parameters] hold the values the formulas saw (a sweep member's, when overridden).
  toml::table& parameters = *resolved["parameters"].as_table();
  for (const auto& [name, value] : r.context.parameters) parameters.insert_or_assign(name, value);

  read_scene_table(r, root.optional_table("scene"), file);
  read_domain(r, root.table("domain"));
  read_solver(r, root.optional_table("solver"));
  read_time(r, root.table("time"));
  read_boundary(r, root.optional_table("boundary"));
  read_materials(r, root.table("materials"));
  read_objects(r, root);
  read_colliders(r, root);
  read_dirichlet(r, root);
  read_domain_releases(r, root);
  read_loads(r, root.optional_table("loads"));
  read_output(r, root.optional_table("output"));
  if (root.has("sweep")) {
    TableReader sweep = root.table("sweep");
    r.scene.sweep = read_sweep(sweep, r.context.parameters);
    sweep.finish();
  }
  root.finish();

  r.scene.resolved_text =
      to_toml(resolved, {"scene", "parameters", "domain", "time", "solver", "boundary", "materials", "objects",
                         "colliders", "dirichlet", "domain_release", "loads", "output", "sweep"});
  r.scene.source_file = file;
  return std::move(r.scene);
}

Scene load_scene(const std::string& path, const ParameterValues& overrides, const LearnedLaws& laws) {
  // Checked before reading: `romp check /dev/urandom` once read gigabytes.
  std::error_code error;
  if (!fs::is_regular_file(path, error))
    throw SceneError(fmt::format("{}: not a regular file (a scene is a TOML file)", path));
  const std::uintmax_t bytes = fs::file_size(path, error);
  if (!error && bytes > kMaxSceneBytes)
    throw SceneError(
        fmt::format("{}: {} bytes; a scene file may hold at most {} (meshes and models are files of "
                    "their own)",
                    path, bytes, kMaxSceneBytes));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(fmt::format("{}: cannot open the scene file", path));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_scene(text.str(), path, overrides, laws);
}

}  // namespace romp::scene
