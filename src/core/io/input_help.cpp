// Nearest-keyword suggestions, the units bodies need, and the hint that a mesh is in millimetres.
#include "io/input_help.h"

#include <algorithm>
#include <cstdio>

namespace fracdem
{

// Optimal string alignment: Levenshtein plus the swap of two neighbouring characters, the most
// common slip of the keyboard ("poisosn").
int edit_distance(const std::string& a, const std::string& b)
{
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1));
  for (std::size_t i = 0; i <= n; ++i)
    d[i][0] = static_cast<int>(i);
  for (std::size_t j = 0; j <= m; ++j)
    d[0][j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= n; ++i)
    for (std::size_t j = 1; j <= m; ++j) {
      const int cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[n][m];
}

std::string nearest_word(const std::string& word, const std::vector<std::string>& candidates)
{
  const int limit = std::max(2, static_cast<int>(word.size()) / 3);
  std::string best;
  int best_distance = limit + 1;
  for (const std::string& c : candidates) {
    const int dist = edit_distance(word, c);
    if (dist < best_distance) {
      best = c;
      best_distance = dist;
    }
  }
  return best;
}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates)
{
  const std::string near = nearest_word(word, candidates);
  return near.empty() ? "" : "; did you mean '" + near + "'?";
}

std::string body_units_error(const std::string& host_units)
{
  if (host_units == kBodyUnits) return "";
  const std::string given = host_units == "lj"
                                ? "'units lj' (the default of an input without a 'units' command)"
                                : "'units " + host_units + "'";
  return std::string("needs 'units ") + kBodyUnits + "' (its mesh, density, youngs, strength and " +
         "other values are read in metres, kg/m^3, Pa, J/m^2), but the input has " + given +
         "; write 'units " + kBodyUnits + "' before the simulation box is created and give " +
         "every value in SI";
}

double largest_side(const std::vector<double>& xyz)
{
  double side = 0;
  for (std::size_t d = 0; d < 3 && d < xyz.size(); ++d) {
    double lo = xyz[d], hi = xyz[d];
    for (std::size_t i = d; i < xyz.size(); i += 3) {
      lo = std::min(lo, xyz[i]);
      hi = std::max(hi, xyz[i]);
    }
    side = std::max(side, hi - lo);
  }
  return side;
}

std::string mesh_unit_hint(double h, double limit, double extent)
{
  const double ratio = h / limit;
  const bool mm_sized = ratio >= 100 && ratio <= 1000;
  const bool huge = extent > 100 && limit < 1;
  if (!mm_sized && !huge) return "";
  char size[32];
  std::snprintf(size, sizeof size, "%g", extent);
  return std::string(" The mesh (") + size + " across) may be in millimetres: fracdem takes SI " +
         "values, so its coordinates are metres; 'scale 0.001' on fix fem/body converts a mesh " +
         "drawn in mm.";
}

} // namespace fracdem
