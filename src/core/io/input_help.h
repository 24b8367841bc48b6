// Input errors that point at the fix: the nearest known keyword, the host's units, a mesh in mm.
#pragma once

#include <string>
#include <vector>

namespace fracdem
{

// Edits (insert, delete, substitute one character, or swap two neighbours) that turn a into b.
int edit_distance(const std::string& a, const std::string& b);

// The candidate nearest to `word` by edit_distance (the first of equals), or "" when none lies
// within max(2, |word| / 3) edits: a suggestion further off misleads more than it helps.
std::string nearest_word(const std::string& word, const std::vector<std::string>& candidates);

// "; did you mean 'youngs'?" for nearest_word, or "" when nothing is near. Appended to an
// "unknown keyword 'young'" message by every keyword table.
std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates);

// The unit style bodies take: mesh coordinates, densities, moduli, strengths and fracture
// energies are read as SI values (m, kg/m^3, Pa, J/m^2).
constexpr const char* kBodyUnits = "si";

// "" when a body can run under the host's `units` style, else the error text (without the
// command's name): which units the command needs, what the host has and the line to add.
std::string body_units_error(const std::string& host_units);

// The largest side of the bounding box of points xyz (x0 y0 z0 x1 y1 z1 ...); 0 for none.
double largest_side(const std::vector<double>& xyz);

// A sentence for the snap-back error when the mesh looks like it was drawn in millimetres: its
// widest element (h) is 100 to 1000 times the snap-back limit, or its bounding box (largest side,
// extent) exceeds 100 m while the limit is below 1 m. Else "".
std::string mesh_unit_hint(double h, double limit, double extent);

} // namespace fracdem
