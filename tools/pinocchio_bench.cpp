// Times Pinocchio's RNEA, CRBA and ABA exactly as `tumble dynamics --bench` times tumble's: 2000
// random states (angles in [-1, 1], unit quaternions, velocities and torques in [-1, 1]), swept 10
// times in timed chunks of 20 calls after a warm-up pass; the median chunk gives the time per call.
// Prints {"nv", "rnea_us", "crba_us", "aba_us"}.
//
// The model comes from tools/pinocchio_export.py (Pinocchio's own joint types, placements and
// inertias as text), so that only Pinocchio's headers are needed: every algorithm is compiled here,
// with the flags below, and no compiled Pinocchio library is linked.
//
//   VENV=/tmp/venv-pin; P=$(ls -d $VENV/lib/python3*/site-packages/cmeel.prefix)
//   $VENV/bin/python tools/pinocchio_export.py ROBOT.urdf [--floating] > /tmp/robot.pinmodel
//   g++ -O3 -march=native -DNDEBUG -std=c++17 -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30 \
//       -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12 tools/pinocchio_bench.cpp -I$P/include -I/usr/include/eigen3 \
//       -o /tmp/pinocchio_bench
//   /tmp/pinocchio_bench /tmp/robot.pinmodel [STATES]
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <random>
#include <vector>

using pinocchio::Data;
using pinocchio::Model;
using Vec = Eigen::VectorXd;

// The median time per call over timed chunks of 20 consecutive states, the states swept 10 times
// after a warm-up pass (as tumble's `median_time`).
template <class F>
double median_time(size_t states, F f) {
  const size_t chunk = 20;
  for (size_t s = 0; s < states; ++s) f(s);
  std::vector<double> times;
  for (int p = 0; p < 10; ++p) {
    for (size_t start = 0; start < states; start += chunk) {
      size_t end = std::min(start + chunk, states);
      auto clock = std::chrono::steady_clock::now();
      for (size_t s = start; s < end; ++s) f(s);
      std::chrono::duration<double, std::micro> d = std::chrono::steady_clock::now() - clock;
      times.push_back(d.count() / double(end - start));
    }
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

static bool add_joint(Model& model, const std::string& kind, int parent, const pinocchio::SE3& placement,
                      const Eigen::Vector3d& axis, const std::string& name) {
  using namespace pinocchio;
  if (kind == "JointModelRX") model.addJoint(parent, JointModelRX(), placement, name);
  else if (kind == "JointModelRY") model.addJoint(parent, JointModelRY(), placement, name);
  else if (kind == "JointModelRZ") model.addJoint(parent, JointModelRZ(), placement, name);
  else if (kind == "JointModelRevoluteUnaligned") model.addJoint(parent, JointModelRevoluteUnaligned(axis), placement, name);
  else if (kind == "JointModelRUBX") model.addJoint(parent, JointModelRUBX(), placement, name);
  else if (kind == "JointModelRUBY") model.addJoint(parent, JointModelRUBY(), placement, name);
  else if (kind == "JointModelRUBZ") model.addJoint(parent, JointModelRUBZ(), placement, name);
  else if (kind == "JointModelPX") model.addJoint(parent, JointModelPX(), placement, name);
  else if (kind == "JointModelPY") model.addJoint(parent, JointModelPY(), placement, name);
  else if (kind == "JointModelPZ") model.addJoint(parent, JointModelPZ(), placement, name);
  else if (kind == "JointModelPrismaticUnaligned") model.addJoint(parent, JointModelPrismaticUnaligned(axis), placement, name);
  else if (kind == "JointModelFreeFlyer") model.addJoint(parent, JointModelFreeFlyer(), placement, name);
  else return false;
  return true;
}

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s ROBOT.pinmodel [STATES]\n", argv[0]);
    return 2;
  }
  size_t states = argc > 2 ? std::strtoul(argv[2], nullptr, 10) : 2000;
  Model model;
  std::ifstream in(argv[1]);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string kind, name;
    int parent;
    Eigen::Vector3d p, axis, com;
    Eigen::Matrix3d r, inertia;
    double mass, ixx, ixy, ixz, iyy, iyz, izz;
    s >> kind >> parent >> p[0] >> p[1] >> p[2];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) s >> r(i, j);
    s >> axis[0] >> axis[1] >> axis[2] >> mass >> com[0] >> com[1] >> com[2] >> ixx >> ixy >> ixz >> iyy >> iyz >> izz >> name;
    if (!s || !add_joint(model, kind, parent, pinocchio::SE3(r, p), axis, name)) {
      std::fprintf(stderr, "bad line: %s\n", line.c_str());
      return 2;
    }
    inertia << ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz;
    model.appendBodyToJoint(model.njoints - 1, pinocchio::Inertia(mass, com, inertia), pinocchio::SE3::Identity());
  }
  Data data(model);
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec> qs, vs, ts;
  for (size_t s = 0; s < states; ++s) {
    Vec lower = Vec::Constant(model.nq, -1.0), upper = Vec::Constant(model.nq, 1.0);
    qs.push_back(pinocchio::randomConfiguration(model, lower, upper));
    Vec v(model.nv), t(model.nv);
    for (int k = 0; k < model.nv; ++k) { v[k] = u(rng); t[k] = u(rng); }
    vs.push_back(v);
    ts.push_back(t);
  }
  double sink = 0;
  double rnea_us = median_time(states, [&](size_t s) { sink += pinocchio::rnea(model, data, qs[s], vs[s], ts[s])[0]; });
  double crba_us = median_time(states, [&](size_t s) { sink += pinocchio::crba(model, data, qs[s])(0, 0); });
  double aba_us = median_time(states, [&](size_t s) { sink += pinocchio::aba(model, data, qs[s], vs[s], ts[s])[0]; });
  std::printf("{\"nv\":%d,\"rnea_us\":%.4f,\"crba_us\":%.4f,\"aba_us\":%.4f}\n", model.nv, rnea_us, crba_us, aba_us);
  return sink == 12345.678 ? 1 : 0;
}
