// Times Pinocchio's RNEA, CRBA and ABA exactly as `tumble dynamics --bench` times tumble's: 2000
// random states (angles in [-1, 1], unit quaternions, velocities and torques in [-1, 1]), swept 10
// times in timed chunks of 20 calls after a warm-up pass; the median chunk gives the time per call.
// Prints {"nv", "rnea_us", "crba_us", "aba_us"}.
//
// Build (Pinocchio and its headers from `pip install pin`, Eigen from the system):
//   P=$VENV/lib/python3.*/site-packages/cmeel.prefix
//   g++ -O3 -march=native -DNDEBUG -std=c++17 tools/pinocchio_bench.cpp -I$P/include -I/usr/include/eigen3 \
//       -L$P/lib -Wl,-rpath,$P/lib -lpinocchio_parsers -lpinocchio_default -o /tmp/pinocchio_bench
// Run: /tmp/pinocchio_bench ROBOT.urdf [--floating] [STATES]
#include <pinocchio/multibody.hpp>
#include <pinocchio/parsers/urdf.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
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

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s ROBOT.urdf [--floating] [STATES]\n", argv[0]);
    return 2;
  }
  bool floating = false;
  size_t states = 2000;
  for (int i = 2; i < argc; ++i) {
    if (std::strcmp(argv[i], "--floating") == 0) floating = true;
    else states = std::strtoul(argv[i], nullptr, 10);
  }
  Model model;
  if (floating) pinocchio::urdf::buildModel(argv[1], pinocchio::JointModelFreeFlyer(), model);
  else pinocchio::urdf::buildModel(argv[1], model);
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
