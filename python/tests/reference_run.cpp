// predvs_py_reference — the C++ side of python/tests/test_against_cpp.py: runs predictors over a
// track CSV (app/track_csv.h, any number of points) and writes, after every row, each channel's
// estimate at t + horizon and its innovation, with %.17g (exact round trip of a double).
//
// Usage: predvs_py_reference TRACK.csv OUT.csv HORIZON_S SPEC...
//   SPEC = NAME or NAME:KEY=VALUE:KEY=VALUE (numbers, or `auto`).
// Channels: u_0, v_0, u_1, v_1, ... One update per row: update(t) alone when every channel is NaN
// (the predict-only step), else update(t, z) with NaN for the channels not measured.
// Output columns: spec,row,channel,x0,x1,x2,P00,P01,P02,P10,P11,P12,P20,P21,P22,eps,S,valid
// (entries past the predictor's state size are nan).
#include "track_csv.h"

#include "predvs/predictors/predictor.h"

#include <Eigen/Core>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct Spec {
  std::string label, name;
  predvs::Params params;
};

Spec parseSpec(const std::string& text) {
  Spec s;
  s.label = text;
  std::stringstream ss(text);
  std::string part;
  std::getline(ss, s.name, ':');
  while (std::getline(ss, part, ':')) {
    const auto eq = part.find('=');
    if (eq == std::string::npos) throw std::invalid_argument("spec '" + text + "': expected KEY=VALUE, got '" + part + "'");
    const std::string key = part.substr(0, eq), value = part.substr(eq + 1);
    if (value == "auto") {
      s.params.setText(key, value);
      continue;
    }
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0') throw std::invalid_argument("spec '" + text + "': bad number '" + value + "'");
    s.params.set(key, v);
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 5) throw std::invalid_argument("usage: predvs_py_reference TRACK.csv OUT.csv HORIZON_S SPEC...");
    const predvs::FeatureTrack track = predvs::readFeatureTrack(argv[1]);
    const double horizon_s = std::strtod(argv[3], nullptr);
    const int m = 2 * track.points();
    FILE* out = std::fopen(argv[2], "w");
    if (!out) throw std::invalid_argument(std::string(argv[2]) + ": cannot write");
    std::fprintf(out, "spec,row,channel,x0,x1,x2,P00,P01,P02,P10,P11,P12,P20,P21,P22,eps,S,valid\n");
    for (int a = 4; a < argc; ++a) {
      const Spec spec = parseSpec(argv[a]);
      auto p = predvs::makePredictor(spec.name, m, spec.params);
      for (size_t k = 0; k < track.size(); ++k) {
        Eigen::VectorXd z(m);
        bool any = false;
        for (int q = 0; q < track.points(); ++q) {
          z(2 * q) = track.u_px[static_cast<size_t>(q)][k];
          z(2 * q + 1) = track.v_px[static_cast<size_t>(q)][k];
        }
        for (int c = 0; c < m; ++c) any = any || !std::isnan(z(c));
        if (any)
          p->update(track.t_s[k], z);
        else
          p->update(track.t_s[k]);
        for (int c = 0; c < m; ++c) {
          const predvs::ChannelEstimate e = p->predict(c, track.t_s[k] + horizon_s);
          const predvs::Innovation in = p->innovation(c);
          std::fprintf(out, "%s,%zu,%d", spec.label.c_str(), k, c);
          for (int i = 0; i < 3; ++i) std::fprintf(out, ",%.17g", i < e.x.size() ? e.x(i) : NAN);
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
              std::fprintf(out, ",%.17g", (i < e.P.rows() && j < e.P.cols()) ? e.P(i, j) : NAN);
          std::fprintf(out, ",%.17g,%.17g,%d\n", in.eps, in.S, in.valid ? 1 : 0);
        }
      }
    }
    if (std::fclose(out) != 0) throw std::invalid_argument(std::string(argv[2]) + ": write failed");
  } catch (const std::exception& e) {
    std::cerr << "predvs_py_reference: error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
