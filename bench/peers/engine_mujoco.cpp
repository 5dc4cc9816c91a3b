// MuJoCo 2.2: the Newton ("newton") or PGS ("pgs") solver on its soft contact model, pyramidal
// cones, condim 3, the Euler integrator. The scene becomes an MJCF model: each body a tree under
// the world (a free joint) unless ball joints chain it to another; ball joints along a tree are
// the tree's own joints, so they have no constraint rows.
#include <mujoco/mujoco.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <unistd.h>

#include "peers.hpp"

namespace peers {
namespace {

mjtNum now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// MuJoCo's own handlers print to standard output, where the steps' CSV goes, and append to
// MUJOCO_LOG.TXT in the working directory; these print to standard error instead.
void warning_to_stderr(const char* message) { std::fprintf(stderr, "rbpart_peers: mujoco warning: %s\n", message); }
void error_to_stderr(const char* message) {
  std::fprintf(stderr, "rbpart_peers: mujoco error: %s\n", message);
  std::exit(1);  // MuJoCo does not expect its error handler to return
}

std::string nums(std::initializer_list<double> v) {
  std::ostringstream o;
  o.precision(17);
  for (double x : v) o << (o.tellp() > 0 ? " " : "") << x;
  return o.str();
}

std::string geom_xml(const Body& b) {
  const auto& s = b.shape;
  std::ostringstream o;
  o << "<geom ";
  switch (s.type) {
    case ShapeType::box: o << "type=\"box\" size=\"" << nums({s.half_extents[0], s.half_extents[1], s.half_extents[2]}) << "\""; break;
    case ShapeType::sphere: o << "type=\"sphere\" size=\"" << nums({s.radius}) << "\""; break;
    case ShapeType::capsule: o << "type=\"capsule\" size=\"" << nums({s.radius, s.half_length}) << "\""; break;
  }
  o << " friction=\"" << nums({b.friction}) << " 0 0\"/>";
  return o.str();
}

class MujocoEngine final : public Engine {
 public:
  MujocoEngine(const Scene& scene, const std::string& solver, bool residual, double memory_gib)
      : scene_(scene), residual_(residual) {
    if (solver != "newton" && solver != "pgs") throw std::runtime_error("mujoco: solver is newton or pgs");
    mjcb_time = now_ms;
    mju_user_warning = warning_to_stderr;
    mju_user_error = error_to_stderr;
    const std::string path = "/tmp/rbpart_peers_" + std::to_string(getpid()) + ".xml";
    {
      std::ofstream out(path);
      out << model_xml(solver, memory_gib);
    }
    char error[1000] = "";
    model_ = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
    std::remove(path.c_str());
    if (!model_) throw std::runtime_error(std::string("mujoco: ") + error);
    data_ = mj_makeData(model_);
    if (!data_) throw std::runtime_error("mujoco: cannot allocate mjData (njmax " + std::to_string(model_->njmax) + ")");
    // Initial velocities of the free trees: linear in world axes, angular in the body's axes.
    for (size_t i = 0; i < scene.bodies.size(); ++i) {
      const Body& b = scene.bodies[i];
      if (b.is_static || parent_[i] != -2) continue;
      const int body = body_id_[i], dof = model_->jnt_dofadr[model_->body_jntadr[body]];
      const Vec3 w = mul_transposed(rotation(b.orientation), b.angular_velocity);
      for (int k = 0; k < 3; ++k) data_->qvel[dof + k] = b.velocity[k], data_->qvel[dof + 3 + k] = w[k];
    }
  }

  ~MujocoEngine() override {
    mj_deleteData(data_);
    mj_deleteModel(model_);
  }

  StepReport step() override {
    StepReport report;
    const mjtNum solver_before = data_->timer[mjTIMER_CONSTRAINT].duration;
    const auto start = std::chrono::steady_clock::now();
    mj_step(model_, data_);
    report.total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    report.solve_ms = data_->timer[mjTIMER_CONSTRAINT].duration - solver_before;
    report.contacts = data_->ncon;
    for (int c = 0; c < data_->ncon; ++c) report.max_penetration = std::max(report.max_penetration, -data_->contact[c].dist);
    ++steps_;
    if (data_->warning[mjWARN_CNSTRFULL].number > 0 || data_->warning[mjWARN_CONTACTFULL].number > 0)
      throw std::runtime_error("mujoco: the contact or constraint arrays are full (njmax " + std::to_string(model_->njmax) +
                               ", nconmax " + std::to_string(model_->nconmax) + "); raise --mujoco-memory-gib");
    // A NaN, an infinity or a huge value in qpos, qvel or qacc: mj_step resets the model to its
    // initial state and goes on, so the run would silently start over.
    for (const auto& [warning, what] : {std::pair{mjWARN_BADQPOS, "qpos"}, {mjWARN_BADQVEL, "qvel"}, {mjWARN_BADQACC, "qacc"}})
      if (data_->warning[warning].number > 0)
        throw std::runtime_error("mujoco: unstable at step " + std::to_string(steps_) + ": a bad value in " + what +
                                 " (DOF " + std::to_string(data_->warning[warning].lastinfo) +
                                 "); MuJoCo reset the model to its initial state");
    if (residual_) report.blcp_residual = residual();
    return report;
  }

  std::vector<BodyState> state() const override {
    std::vector<BodyState> out;
    for (size_t i = 0; i < scene_.bodies.size(); ++i) {
      const Body& b = scene_.bodies[i];
      BodyState s;
      if (b.is_static) {
        s.position = b.position, s.orientation = b.orientation;
      } else {
        const int id = body_id_[i];
        for (int k = 0; k < 3; ++k) s.position[k] = data_->xpos[3 * id + k];
        for (int k = 0; k < 4; ++k) s.orientation[k] = data_->xquat[4 * id + k];
        mjtNum v[6];
        mj_objectVelocity(model_, data_, mjOBJ_BODY, id, v, 0);  // [angular, linear], world axes
        s.angular_velocity = {v[0], v[1], v[2]};
        s.velocity = {v[3], v[4], v[5]};
      }
      out.push_back(s);
    }
    return out;
  }

  std::string settings_json() const override {
    const mjOption& o = model_->opt;
    int max_points = 0;  // the most contacts one geom pair had at the last step
    for (int c = 0; c < data_->ncon; ++c) {
      int n = 0;
      for (int d = 0; d < data_->ncon; ++d)
        n += data_->contact[d].geom1 == data_->contact[c].geom1 && data_->contact[d].geom2 == data_->contact[c].geom2;
      max_points = std::max(max_points, n);
    }
    std::ostringstream s;
    s << "{\"engine\": \"MuJoCo " << mj_version() << "\", \"precision\": \"double\", \"solver\": \""
      << (o.solver == mjSOL_NEWTON ? "Newton" : o.solver == mjSOL_PGS ? "PGS" : "CG") << "\", \"iterations\": " << o.iterations
      << ", \"tolerance\": " << o.tolerance << ", \"noslip_iterations\": " << o.noslip_iterations
      << ", \"cone\": \"" << (o.cone == mjCONE_PYRAMIDAL ? "pyramidal" : "elliptic") << "\", \"impratio\": " << o.impratio
      << ", \"integrator\": \"" << (o.integrator == mjINT_EULER ? "Euler" : "other") << "\", \"jacobian\": \""
      << (mj_isSparse(model_) ? "sparse" : "dense") << "\", \"solref\": [" << model_->geom_solref[0] << ", "
      << model_->geom_solref[1] << "], \"solimp\": [" << model_->geom_solimp[0] << ", " << model_->geom_solimp[1]
      << ", " << model_->geom_solimp[2] << "], \"margin\": " << model_->geom_margin[0]
      << ", \"condim\": " << model_->geom_condim[0] << ", \"njmax\": " << model_->njmax
      << ", \"nconmax\": " << model_->nconmax << ", \"max_points_per_pair_seen_last_step\": " << max_points
      << ", \"friction\": \"max(mu_a, mu_b) per pair (equal to sqrt(mu_a mu_b) when all bodies share mu)\""
      << ", \"sleeping\": \"none in MuJoCo 2.2\"}";
    return s.str();
  }

 private:
  // Bodies joined by ball joints nest as a tree; the first body of each tree gets a free joint.
  std::string model_xml(const std::string& solver, double memory_gib) {
    const size_t n = scene_.bodies.size();
    parent_.assign(n, -2);  // -2: a free tree root; -1: hung from the world by a ball joint
    std::vector<std::vector<std::pair<int, Vec3>>> children(n);
    std::vector<bool> placed(n, false);
    std::vector<std::vector<std::pair<int, Vec3>>> links(n);
    std::vector<std::pair<int, Vec3>> world_links;
    for (const auto& j : scene_.joints) {
      if (j.b < 0) world_links.push_back({j.a, j.anchor});
      else links[j.a].push_back({j.b, j.anchor}), links[j.b].push_back({j.a, j.anchor});
    }
    std::ostringstream body_xml;
    std::function<void(int, int, const Vec3*)> emit = [&](int i, int parent, const Vec3* anchor) {
      placed[i] = true;
      const Body& b = scene_.bodies[i];
      Vec3 pos = b.position;
      Quat quat = b.orientation;
      if (parent >= 0) {
        const Body& p = scene_.bodies[parent];
        pos = mul_transposed(rotation(p.orientation), sub(b.position, p.position));
        quat = conjugate_times(p.orientation, b.orientation);
      }
      body_xml << "<body pos=\"" << nums({pos[0], pos[1], pos[2]}) << "\" quat=\"" << nums({quat[0], quat[1], quat[2], quat[3]})
               << "\">";
      if (anchor) {
        const Vec3 local = mul_transposed(rotation(b.orientation), sub(*anchor, b.position));
        body_xml << "<joint type=\"ball\" pos=\"" << nums({local[0], local[1], local[2]}) << "\"/>";
      } else {
        body_xml << "<freejoint/>";
      }
      body_xml << "<inertial pos=\"0 0 0\" mass=\"" << nums({b.mass}) << "\" diaginertia=\""
               << nums({b.inertia[0], b.inertia[1], b.inertia[2]}) << "\"/>" << geom_xml(b);
      order_.push_back(i);
      for (const auto& [other, at] : links[i]) {
        if (placed[other]) {
          if (other != parent) throw std::runtime_error("mujoco: a loop of ball joints needs an equality constraint; not supported");
          continue;
        }
        parent_[other] = i;
        emit(other, i, &at);
      }
      body_xml << "</body>";
    };
    for (const auto& [i, at] : world_links) {
      if (placed[i]) throw std::runtime_error("mujoco: a body hung from the world twice; not supported");
      parent_[i] = -1;
      emit(i, -1, &at);
    }
    // A free tree is rooted at its centre, the body from which the tree is shallowest: MJCF nests
    // a body per level and MuJoCo's XML parser refuses more than 100 levels (a 100-link chain).
    auto depth_from = [&](int root) {
      std::vector<int> depth(n, -1), queue{root};
      depth[root] = 0;
      int deepest = 0;
      for (size_t k = 0; k < queue.size(); ++k)
        for (const auto& link : links[queue[k]])
          if (depth[link.first] < 0) {
            depth[link.first] = depth[queue[k]] + 1;
            deepest = std::max(deepest, depth[link.first]);
            queue.push_back(link.first);
          }
      return std::make_pair(deepest, queue);
    };
    int dynamic = 0;
    for (size_t i = 0; i < n; ++i) {
      dynamic += !scene_.bodies[i].is_static;
      if (scene_.bodies[i].is_static || placed[i]) continue;
      int root = static_cast<int>(i), best = depth_from(root).first;
      for (int candidate : depth_from(root).second)
        if (const int d = depth_from(candidate).first; d < best) best = d, root = candidate;
      emit(root, -1, nullptr);
    }
    // MuJoCo 2.2 sizes mjData for njmax rows up front (efc_AR is njmax x njmax) and zeroes it: take
    // the most rows that fit the memory given, at most 4 pyramid rows x 16 contacts per body.
    // mj_makeData fails here past about 2 GiB (measured on a 200-box pile: 1.9 GiB allocates,
    // 2.5 GiB does not), so the memory given is capped below that.
    const double bytes = std::min(memory_gib, 1.9) * (1u << 30), nv = 6.0 * dynamic;
    const double fit = (-24 * nv + std::sqrt(576 * nv * nv + 4 * 12 * bytes)) / (2 * 12);
    const int njmax = static_cast<int>(std::min(fit, 64.0 * dynamic + 1000));
    std::ostringstream xml;
    xml.precision(17);
    xml << "<mujoco model=\"" << scene_.name << "\"><compiler angle=\"radian\" inertiafromgeom=\"false\"/>"
        << "<size njmax=\"" << njmax << "\" nconmax=\"" << njmax / 4 << "\"/>"
        << "<option timestep=\"" << scene_.dt << "\" gravity=\"" << nums({scene_.gravity[0], scene_.gravity[1], scene_.gravity[2]})
        << "\" integrator=\"Euler\" cone=\"pyramidal\" jacobian=\"sparse\" solver=\"" << (solver == "newton" ? "Newton" : "PGS")
        << "\"/><default><geom condim=\"3\"/></default><worldbody>";
    for (size_t i = 0; i < n; ++i) {
      const Body& b = scene_.bodies[i];
      if (!b.is_static) continue;
      std::string g = geom_xml(b);
      g.insert(5, " pos=\"" + nums({b.position[0], b.position[1], b.position[2]}) + "\" quat=\"" +
                      nums({b.orientation[0], b.orientation[1], b.orientation[2], b.orientation[3]}) + "\"");
      xml << g;
    }
    xml << body_xml.str() << "</worldbody></mujoco>";
    // MJCF numbers bodies in document order: the world 0, then the emitted bodies.
    body_id_.assign(n, 0);
    for (size_t k = 0; k < order_.size(); ++k) body_id_[order_[k]] = static_cast<int>(k) + 1;
    return xml.str();
  }

  // MuJoCo's constraint problem in its dual form: forces f >= 0 on the pyramid edges, w = AR f + b
  // with AR = J M^-1 J^T + R and b = efc_b = J qacc_smooth - aref (nodes: kinematic trees).
  double residual() {
    const mjModel* m = model_;
    mjData* d = data_;
    const int nefc = d->nefc, nv = m->nv;
    if (nefc == 0) return 0;
    std::vector<mjtNum> qfrc(nv), qacc(nv), jqacc(nefc), column(nv), x(nv);
    mj_mulJacTVec(m, d, qfrc.data(), d->efc_force);
    mj_solveM(m, d, qacc.data(), qfrc.data(), 1);
    mj_mulJacVec(m, d, jqacc.data(), qacc.data());
    std::vector<Row> rows(nefc);
    for (int j = 0; j < nefc; ++j) {
      // The row's diagonal: J_j M^-1 J_j^T, one solve with its (sparse) row.
      std::fill(column.begin(), column.end(), 0.0);
      const int adr = d->efc_J_rowadr[j];
      for (int k = 0; k < d->efc_J_rownnz[j]; ++k) column[d->efc_J_colind[adr + k]] = d->efc_J[adr + k];
      mj_solveM(m, d, x.data(), column.data(), 1);
      double a = d->efc_R[j];
      for (int k = 0; k < d->efc_J_rownnz[j]; ++k) a += d->efc_J[adr + k] * x[d->efc_J_colind[adr + k]];
      Row& r = rows[j];
      if (d->efc_type[j] != mjCNSTR_CONTACT_PYRAMIDAL)
        throw std::runtime_error("mujoco: a constraint row other than a pyramidal contact; the residual does not cover it");
      const mjContact& c = d->contact[d->efc_id[j]];
      r.node_a = tree(m->geom_bodyid[c.geom1]);
      r.node_b = tree(m->geom_bodyid[c.geom2]);
      r.lambda = d->efc_force[j];
      r.a_jj = a;
      r.q = d->efc_b[j];
      const double w = jqacc[j] + d->efc_R[j] * d->efc_force[j] + d->efc_b[j];
      r.inner = r.lambda - w / a;
      r.lo = 0;
      r.hi = INFINITY;
    }
    return natural_map_residual(rows, m->nbody);
  }

  int tree(int body) const { return body == 0 ? -1 : model_->body_rootid[body]; }

  const Scene& scene_;
  bool residual_;
  mjModel* model_ = nullptr;
  mjData* data_ = nullptr;
  int steps_ = 0;
  std::vector<int> parent_, order_, body_id_;
};

}  // namespace

std::unique_ptr<Engine> make_mujoco(const Scene& scene, const std::string& solver, bool residual, double memory_gib) {
  return std::make_unique<MujocoEngine>(scene, solver, residual, memory_gib);
}

}  // namespace peers
