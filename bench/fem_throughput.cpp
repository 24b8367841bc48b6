// FE throughput benchmark: element-steps per second per core for tet4/tri3/quad4, elastic and
// corotational.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "fem/fe_space.h"
#include "io/mesh_generators.h"

using namespace fracdem;

int main(int argc, char** argv)
{
  const std::string out = argc > 1 ? argv[1] : "fem_throughput.csv";
  FILE* fp = fopen(out.c_str(), "w");
  if (!fp) {
    fprintf(stderr, "cannot write %s\n", out.c_str());
    return 1;
  }
  fprintf(fp, "element,model,elements,steps,repetition,seconds,elem_steps_per_s\n");
  struct Case {
    const char* name;
    Mesh mesh;
  };
  std::vector<Case> cases;
  cases.push_back({"tet4", make_box_tet_mesh(30, 30, 30, 1, 1, 1)});
  cases.push_back({"tri3", make_rect_mesh(300, 300, 1, 1, {0, 0}, ElemType::Tri3)});
  cases.push_back({"quad4", make_rect_mesh(300, 300, 1, 1, {0, 0}, ElemType::Quad4)});
  printf("%-6s %-13s %10s %14s\n", "elem", "model", "elements", "Melem-steps/s");
  for (auto& c : cases) {
    for (Kinematics k : {Kinematics::SmallStrain, Kinematics::Corotational}) {
      Material m;
      m.E = 1e9;
      m.nu = 0.3;
      m.rho = 1000;
      m.kinematics = k;
      FeSpace fs;
      fs.build(c.mesh, m);
      std::vector<double> x(c.mesh.X), f(x.size());
      for (size_t i = 0; i < x.size(); ++i)
        x[i] += 1e-4 * ((i * 2654435761u) % 1000) / 1000.0;
      const int ne = c.mesh.num_elems();
      const int steps = std::max(5, static_cast<int>(2e7 / ne));
      std::vector<double> rates;
      for (int rep = 0; rep < 5; ++rep) {
        int inv = -1;
        auto t0 = std::chrono::steady_clock::now();
        double e = 0;
        for (int s = 0; s < steps; ++s) {
          std::fill(f.begin(), f.end(), 0.0);
          e += fs.add_internal_forces(c.mesh, x.data(), 0, ne, f.data(), nullptr, &inv);
        }
        const double sec =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double rate = double(ne) * steps / sec;
        rates.push_back(rate);
        fprintf(fp, "%s,%s,%d,%d,%d,%.6f,%.1f\n", c.name,
                k == Kinematics::SmallStrain ? "elastic" : "corotational", ne, steps, rep, sec,
                rate);
        if (e < 0) printf("negative energy?\n"); // keeps the loop from being optimised away
      }
      std::sort(rates.begin(), rates.end());
      printf("%-6s %-13s %10d %14.2f\n", c.name,
             k == Kinematics::SmallStrain ? "elastic" : "corotational", ne, rates[2] / 1e6);
    }
  }
  fclose(fp);
  printf("wrote %s (median of 5 repetitions shown)\n", out.c_str());
  return 0;
}
