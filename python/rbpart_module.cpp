// The Python module `rbpart` (pybind11): a World built from a built-in scene, a scene file or a
// scene as a dict, stepped, and read as NumPy arrays; and rbpart's partitioners on any graph given
// as METIS's CSR arrays. Options carry the names of include/rbpart/params.hpp's fields and the CLI's
// domains; a bad value raises ValueError naming it (README, "Embedding: C++ and Python").
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <rbpart/world.hpp>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/metis_graph.hpp"
#include "io/run_params.hpp"
#include "io/scene_json.hpp"
#include "io/stats_csv.hpp"
#include "io/text_format.hpp"
#include "partition/partition.hpp"
#include "scene/limits.hpp"
#include "scenes/scenes.hpp"
#include "step/world_internals.hpp"

namespace py = pybind11;

namespace rbpart {
namespace {

// Everything a World or a partition takes besides the scene.
struct RunOptions {
  StepParams step;
  SolverParams solver;
  PartitionParams partition;
  double dt = 0;  // 0: the scene's
};

// Where a numeric option lies: lo < x or lo <= x, x < hi or x <= hi.
struct Domain {
  double lo, hi;
  bool lo_open, hi_open;
  bool contains(double x) const {
    return (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
  }
  std::string text() const {
    return (lo_open ? "(" : "[") + round_trip(lo) + ", " + round_trip(hi) + (hi_open ? ")" : "]");
  }
};
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr Domain kAtLeastZero{0, kInf, false, true}, kPositive{0, kInf, true, true}, kAtLeastOne{1, kInf, false, true},
    kAboveOne{1, kInf, true, true}, kErp{0, 1, true, false}, kTauMix{0, 1, true, true},
    kDt{0, limits::kMaxDt, true, false};

// A numeric option: its domain (the CLI's, apps/rbpart/simulate.cpp and partition.cpp), whether it
// is a whole number, whether rbpart.partition takes it too, and the field it sets.
struct NumericOption {
  const char* name;
  Domain domain;
  bool whole, partition;
  void (*set)(RunOptions&, double);
};

const std::vector<NumericOption>& numeric_options() {
  static const std::vector<NumericOption> options = {
      {"dt", kDt, false, false, [](RunOptions& o, double x) { o.dt = x; }},
      {"erp", kErp, false, false, [](RunOptions& o, double x) { o.step.erp = x; }},
      {"slop", kAtLeastZero, false, false, [](RunOptions& o, double x) { o.step.slop = x; }},
      {"sigma_floor", kPositive, false, false, [](RunOptions& o, double x) { o.step.sigma_floor = x; }},
      {"contact_prox", kAtLeastZero, false, false, [](RunOptions& o, double x) { o.step.contact_prox = x; }},
      {"contact_margin", kAtLeastZero, false, false, [](RunOptions& o, double x) { o.step.contact_margin = x; }},
      {"threads", kAtLeastZero, true, false, [](RunOptions& o, double x) { o.solver.threads = int(x); }},
      {"max_factorizations", kPositive, true, false,
       [](RunOptions& o, double x) { o.solver.max_factorizations = int(x); }},
      {"pgs_iterations", kPositive, true, false, [](RunOptions& o, double x) { o.solver.pgs_iterations = int(x); }},
      {"pgs_tolerance", kAtLeastZero, false, false, [](RunOptions& o, double x) { o.solver.pgs_tolerance = x; }},
      {"nmax", kAtLeastOne, true, true, [](RunOptions& o, double x) { o.partition.nmax = int(x); }},
      {"tau_mr", kAboveOne, false, true, [](RunOptions& o, double x) { o.partition.tau_mr = x; }},
      {"tau_mix", kTauMix, false, true, [](RunOptions& o, double x) { o.partition.tau_mix = x; }}};
  return options;
}

SolverKind parse_solver(const std::string& name) {
  if (name == "direct") return SolverKind::Direct;
  if (name == "pgs") return SolverKind::Pgs;
  if (name == "substructured") return SolverKind::Substructured;
  throw InputError("unknown solver '" + name + "' (direct, pgs or substructured)");
}

// Sets one keyword option; `partition_only` for rbpart.partition, which takes no solver options.
void set_option(RunOptions& o, const std::string& name, const py::handle& value, bool partition_only) {
  if (name == "partitioner") return void(o.partition.partitioner = parse_partitioner(py::cast<std::string>(value)));
  if (name == "refiner") return void(o.partition.refiner = parse_refiner(py::cast<std::string>(value)));
  if (name == "debug_checks") return void(o.partition.debug_checks = py::cast<bool>(value));
  if (name == "solver" && !partition_only) return void(o.solver.kind = parse_solver(py::cast<std::string>(value)));
  for (const NumericOption& option : numeric_options()) {
    if (name != option.name || (partition_only && !option.partition)) continue;
    if (py::isinstance<py::bool_>(value) || !(py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value)))
      throw InputError(name + " must be a number (got " + py::cast<std::string>(py::repr(value)) + ")");
    const double x = py::cast<double>(value);
    if (!option.domain.contains(x))
      throw InputError(name + " must lie in " + option.domain.text() + " (got " + round_trip(x) + ")");
    if (option.whole && (x != std::floor(x) || x > std::numeric_limits<int>::max()))
      throw InputError(name + " must be a whole number below 2^31 (got " + round_trip(x) + ")");
    option.set(o, x);
    return;
  }
  throw InputError("unknown option '" + name + "'");
}

RunOptions run_options(const py::kwargs& kwargs, bool partition_only) {
  RunOptions o;
  for (const auto& [key, value] : kwargs) set_option(o, py::cast<std::string>(key), value, partition_only);
  return o;
}

// A scene: a built-in name (with `parameters`), a scene file's path, or a scene file's content as
// a dict.
SceneDef make_scene(const py::object& scene, const py::dict& parameters) {
  std::vector<std::pair<std::string, std::string>> overrides;
  for (const auto& [key, value] : parameters)
    overrides.emplace_back(py::cast<std::string>(key), py::cast<std::string>(py::str(value)));
  if (py::isinstance<py::dict>(scene)) {
    if (!overrides.empty()) throw InputError("parameters apply to built-in scenes only, not to a scene dict");
    const std::string text = py::cast<std::string>(py::module_::import("json").attr("dumps")(scene));
    return parse_scene(text, "scene");
  }
  return load_scene(py::cast<std::string>(py::str(scene)), overrides);
}

std::unique_ptr<World> make_world(const py::object& scene, const py::object& parameters, const py::kwargs& kwargs) {
  const RunOptions o = run_options(kwargs, false);
  SceneDef def = make_scene(scene, parameters.is_none() ? py::dict() : py::dict(parameters));
  if (o.dt > 0) def.dt = o.dt;
  return std::make_unique<World>(std::move(def), o.step, o.solver, o.partition);
}

// One row per body (or contact) of `columns` numbers, filled by `fill(row, out)`.
template <class Fill>
py::array_t<double> rows_array(int rows, int columns, Fill fill) {
  py::array_t<double> a({rows, columns});
  auto m = a.mutable_unchecked<2>();
  for (int i = 0; i < rows; ++i) fill(i, &m(i, 0));
  return a;
}

void put(double* out, const Vec3& v) {
  for (int k = 0; k < 3; ++k) out[k] = v[k];
}

// Body states as an n x 3 array of one of their vectors.
py::array_t<double> body_vectors(const World& world, Vec3 BodyState::*field) {
  return rows_array(world.body_count(), 3, [&](int i, double* out) { put(out, world.body_state(i).*field); });
}

py::dict stats_dict(const StepStats& stats) {
  py::dict d;
  const auto values = StatsCsvWriter::values(stats);
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (StatsCsvWriter::column_kind(i) == StatsCsvWriter::ColumnKind::Count)
      d[StatsCsvWriter::kColumns[i]] = static_cast<long long>(values[i]);
    else
      d[StatsCsvWriter::kColumns[i]] = values[i];
  }
  return d;
}

py::dict contacts_dict(const World& world) {
  const std::vector<ContactImpulse> c = world.contacts();
  const int n = static_cast<int>(c.size());
  py::array_t<int> a(n), b(n);
  py::array_t<double> distance(n), normal_impulse(n);
  for (int i = 0; i < n; ++i) {
    a.mutable_at(i) = c[i].body_a;
    b.mutable_at(i) = c[i].body_b;
    distance.mutable_at(i) = c[i].distance;
    normal_impulse.mutable_at(i) = c[i].normal_impulse;
  }
  py::dict d;
  d["body_a"] = a;
  d["body_b"] = b;
  d["point"] = rows_array(n, 3, [&](int i, double* out) { put(out, c[i].point); });
  d["normal"] = rows_array(n, 3, [&](int i, double* out) { put(out, c[i].normal); });
  d["distance"] = distance;
  d["normal_impulse"] = normal_impulse;
  d["friction_impulse"] = rows_array(n, 3, [&](int i, double* out) { put(out, c[i].friction_impulse); });
  d["impulse"] = rows_array(n, 3, [&](int i, double* out) { put(out, c[i].impulse()); });
  return d;
}

template <class T>
py::array_t<T> array_of(const std::vector<T>& v) {
  return py::array_t<T>(static_cast<py::ssize_t>(v.size()), v.data());
}

py::dict graph_dict(const ConstraintGraph& g) {
  py::dict d;
  d["xadj"] = array_of(g.offset);
  d["adjncy"] = array_of(g.adjacency);
  d["edge_weights"] = array_of(g.weight);
  d["masses"] = array_of(g.mass);
  d["bodies"] = array_of(g.body_of);
  return d;
}

template <class T>
std::vector<T> vector_of(const py::object& a) {
  if (a.is_none()) return {};
  const auto array = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!array || array.ndim() != 1) throw InputError("expected a one-dimensional array");
  return std::vector<T>(array.data(), array.data() + array.size());
}

// Integer arrays must hold integers: forcecast would truncate 1.5 to 1.
std::vector<int> index_vector(const py::object& a, const char* name) {
  if (!a.is_none()) {
    const py::array array = py::array::ensure(a);
    if (!array || (array.size() > 0 && array.dtype().kind() != 'i' && array.dtype().kind() != 'u'))
      throw InputError(std::string(name) + " must be an array of integers");
  }
  return vector_of<int>(a);
}

py::tuple partition_arrays(const py::object& xadj, const py::object& adjncy, const std::string& partitioner,
                           const std::string& refiner, const py::object& edge_weights, const py::object& masses,
                           const py::object& parts, const py::kwargs& kwargs) {
  RunOptions o = run_options(kwargs, true);
  PartitionParams& params = o.partition;
  params.partitioner = parse_partitioner(partitioner);
  params.refiner = parse_refiner(refiner);
  if (params.partitioner == PartitionerKind::None)
    throw InputError("partitioner none makes no partition (choose bfs, mindp, maxdp, mr, mix or metis)");
  const ConstraintGraph graph = graph_from_arrays(index_vector(xadj, "xadj"), index_vector(adjncy, "adjncy"),
                                                  index_vector(edge_weights, "edge_weights"), vector_of<double>(masses));
  if (!parts.is_none()) {
    if (kwargs.contains("nmax")) throw InputError("give parts or nmax, not both");
    const int k = py::cast<int>(parts);
    if (k < 1) throw InputError("parts must be at least 1 (got " + std::to_string(k) + ")");
    params.nmax = nmax_for_parts(graph.node_count(), k);
  }
  Partition partition;
  PartitionQuality q;
  {
    py::gil_scoped_release release;
    q = partition_and_refine(graph, params, partition);
  }
  py::dict quality;
  quality["parts"] = q.parts;
  quality["edge_cut"] = q.edge_cut;
  quality["interface_rows"] = q.interface_rows;
  quality["interface_bodies"] = q.interface_bodies;
  quality["min_bodies"] = q.min_bodies;
  quality["max_bodies"] = q.max_bodies;
  quality["mean_bodies"] = q.mean_bodies;
  quality["nmax"] = params.nmax;
  quality["partition_ms"] = q.partition_ms;
  quality["refine_ms"] = q.refine_ms;
  return py::make_tuple(array_of(partition.part_of), quality);
}

py::dict scenes_dict() {
  py::dict d;
  for (const SceneInfo& info : builtin_scenes()) {
    py::dict parameters;
    for (const SceneParameter& p : info.parameters) parameters[p.name.c_str()] = p.value;
    d[info.name.c_str()] = py::dict(py::arg("description") = info.description, py::arg("parameters") = parameters);
  }
  return d;
}

}  // namespace
}  // namespace rbpart

PYBIND11_MODULE(rbpart, m) {
  using namespace rbpart;
  m.doc() = "rbpart: stiff rigid multibody simulation with contact, and constraint-graph partitioning";
  py::register_local_exception<InputError>(m, "InputError", PyExc_ValueError);

  m.def("scenes", &scenes_dict, "The built-in scenes: {name: {'description', 'parameters': {name: default}}}.");

  py::class_<World>(m, "World", R"(A scene advancing in time (the CLI's `rbpart simulate`).

World(scene, parameters=None, **options)
  scene       a built-in scene's name (rbpart.scenes()), a scene file's path, or a dict in the
              scene-file format (docs/formats.md#scene-file)
  parameters  a built-in scene's parameters, {name: value}, over its defaults
  options     solver ('direct', 'pgs', 'substructured'), partitioner ('none', 'bfs',
              'mindp', 'maxdp', 'mr', 'mix', 'metis'), refiner ('none', 'kl', 'fm', 'fm-rollback'),
              dt, and the numeric fields of include/rbpart/params.hpp: erp, slop, sigma_floor, contact_prox,
              contact_margin, threads, max_factorizations, pgs_iterations, pgs_tolerance, nmax,
              tau_mr, tau_mix, debug_checks.
Arrays are copies, one row per body in scene order (static bodies included).)")
      .def(py::init(&make_world), py::arg("scene"), py::arg("parameters") = py::none())
      .def(
          "step",
          [](World& w, int n) {
            if (n < 1) throw InputError("step count must be at least 1 (got " + std::to_string(n) + ")");
            const StepStats* last = nullptr;
            {
              py::gil_scoped_release release;
              for (int i = 0; i < n; ++i) last = &w.step();
            }
            return stats_dict(*last);
          },
          py::arg("n") = 1, "Advances n steps; returns the last step's statistics (the stats CSV's columns).")
      .def_property_readonly("time", &World::time)
      .def_property_readonly("step_count", &World::step_count)
      .def_property_readonly("dt", [](const World& w) { return w.scene().dt; })
      .def_property_readonly("body_count", &World::body_count)
      .def_property_readonly("names",
                             [](const World& w) {
                               std::vector<std::string> names;
                               for (const BodyDef& b : w.scene().bodies) names.push_back(b.name);
                               return names;
                             })
      .def_property_readonly("masses",
                             [](const World& w) {
                               py::array_t<double> a(w.body_count());
                               for (int i = 0; i < w.body_count(); ++i) a.mutable_at(i) = w.body_mass(i);
                               return a;
                             },
                             "kg per body (0 for static bodies).")
      .def_property_readonly("is_static",
                             [](const World& w) {
                               py::array_t<bool> a(w.body_count());
                               for (int i = 0; i < w.body_count(); ++i) a.mutable_at(i) = w.scene().bodies[i].is_static;
                               return a;
                             })
      .def_property_readonly("positions", [](const World& w) { return body_vectors(w, &BodyState::position); },
                             "n x 3: each body's shape frame origin (as the scene places it), m.")
      .def_property_readonly("orientations",
                             [](const World& w) {
                               return rows_array(w.body_count(), 4, [&](int i, double* out) {
                                 const Quat q = w.body_state(i).orientation;
                                 out[0] = q.w(), out[1] = q.x(), out[2] = q.y(), out[3] = q.z();
                               });
                             },
                             "n x 4: unit quaternions [w, x, y, z].")
      .def_property_readonly("velocities", [](const World& w) { return body_vectors(w, &BodyState::velocity); },
                             "n x 3: velocity of each centre of mass, m/s.")
      .def_property_readonly("angular_velocities",
                             [](const World& w) { return body_vectors(w, &BodyState::angular_velocity); },
                             "n x 3: angular velocity, rad/s (world frame).")
      .def("contacts", &contacts_dict, R"(The last step's contacts with the impulses the solver gave them, as arrays:
body_a, body_b (scene indices; a is dynamic, b receives the opposite impulse), point and normal
(k x 3; the normal points from b into a), distance (signed, < 0: penetration), normal_impulse
(N s along the normal), friction_impulse and impulse (k x 3, N s, on body a).)")
      .def(
          "apply_force",
          [](World& w, int body, const Vec3& force, const std::optional<Vec3>& point) {
            point ? w.apply_force(body, force, *point) : w.apply_force(body, force);
          },
          py::arg("body"), py::arg("force"), py::arg("point") = py::none(),
          "A force (N) on a dynamic body for the next step only, at its centre of mass or at a world point.")
      .def("apply_torque", &World::apply_torque, py::arg("body"), py::arg("torque"),
           "A torque (N m, world frame) on a dynamic body for the next step only.")
      .def("constraint_graph", [](const World& w) { return graph_dict(world_graph(w)); },
           "The last step's constraint graph as CSR arrays: xadj, adjncy, edge_weights, masses, and the scene "
           "index of each node (bodies); rbpart.partition takes it as it is.")
      .def("parts", [](const World& w) { return array_of(world_partition(w).part_of); },
           "The last step's part id per constraint-graph node (the islands without a partitioner).")
      .def_property_readonly("options",
                             [](const World& w) {
                               py::dict d;
                               for (const auto& [key, value] :
                                    run_parameters(w.step_params(), w.solver_params(), w.partition_params()))
                                 d[key.c_str()] = value;
                               return d;
                             },
                             "Every parameter of the run as text, as the CLI's outputs report them.")
      .def_property_readonly("state_hash", &World::state_hash);

  m.def("partition", &partition_arrays, py::arg("xadj"), py::arg("adjncy"), py::arg("partitioner"),
        py::arg("refiner") = "none", py::kw_only(), py::arg("edge_weights") = py::none(),
        py::arg("masses") = py::none(), py::arg("parts") = py::none(),
        R"(Partitions a graph given as METIS's CSR arrays (0-based; each edge listed from both ends),
as `rbpart partition` does: connected parts of at most nmax nodes.

partition(xadj, adjncy, partitioner, refiner='none', *, edge_weights=None, masses=None, parts=None,
          nmax=32, tau_mr=10, tau_mix=0.5, debug_checks=False) -> (part_ids, quality)
  partitioner  'bfs', 'mindp', 'maxdp', 'mr', 'mix' or 'metis'; refiner 'none', 'kl', 'fm', 'fm-rollback'
  parts        K balanced parts as METIS means it: sets nmax to ceil(n / K)
part_ids is an int32 array, one 0-based part id per node; quality a dict with parts, edge_cut,
interface_rows, interface_bodies, min_bodies, max_bodies, mean_bodies, nmax, partition_ms, refine_ms.)");
}
