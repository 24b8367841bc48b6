// Liquid bridge force kernels: Willett's capillary force, Pitois's viscous force, Lian's rupture.
#include "liquid_bridge.h"

#include "io/input_help.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace fracdem
{

namespace
{

constexpr double kPi = 3.14159265358979323846;
// Willett's denominator 1 + a S^ + b S^^2.
constexpr double kWillettA = 1.05;
constexpr double kWillettB = 2.5;

// int_0^x dt / (1 + a t + b t^2) with 4b > a^2.
double willett_integral(double x)
{
  const double d = std::sqrt(4.0 * kWillettB - kWillettA * kWillettA);
  return 2.0 / d * (std::atan((2.0 * kWillettB * x + kWillettA) / d) - std::atan(kWillettA / d));
}

} // namespace

std::string check_liquid_bridge(const LiquidBridge& b)
{
  std::ostringstream out;
  if (!(b.surface_tension >= 0))
    out << "surface_tension must be >= 0 (got " << b.surface_tension << ")";
  else if (!(b.volume > 0))
    out << "volume must be > 0 (got " << b.volume << ")";
  else if (!(b.contact_angle >= 0 && b.contact_angle < 0.5 * kPi))
    out << "contact_angle must be in radians in [0, pi/2) = [0, 1.5708) (got " << b.contact_angle
        << ")";
  else if (!(b.viscosity >= 0))
    out << "viscosity must be >= 0 (got " << b.viscosity << ")";
  return out.str();
}

double derjaguin_radius(double r1, double r2)
{
  if (r2 <= 0) return 2.0 * r1;
  return 2.0 * r1 * r2 / (r1 + r2);
}

double rupture_distance(const LiquidBridge& b)
{
  return (1.0 + 0.5 * b.contact_angle) * std::cbrt(b.volume);
}

BridgeLaw prepare_bridge(const LiquidBridge& b)
{
  BridgeLaw law;
  law.params = b;
  law.rupture = rupture_distance(b);
  law.two_pi_tension_cos = 2.0 * kPi * b.surface_tension * std::cos(b.contact_angle);
  return law;
}

double capillary_force(const BridgeLaw& law, double r_star, double gap)
{
  if (gap >= law.rupture) return 0.0;
  const double s = std::max(gap, 0.0) * std::sqrt(r_star / law.params.volume);
  return law.two_pi_tension_cos * r_star / (1.0 + kWillettA * s + kWillettB * s * s);
}

double capillary_potential(const BridgeLaw& law, double r_star, double gap)
{
  const double sc = law.rupture;
  if (gap >= sc) return 0.0;
  const double k = std::sqrt(r_star / law.params.volume);
  const double f0 = law.two_pi_tension_cos * r_star;
  const double u0 = -f0 / k * willett_integral(k * sc); // willett_integral(0) = 0
  if (gap <= 0) return u0 + f0 * gap;
  return -f0 / k * (willett_integral(k * sc) - willett_integral(k * gap));
}

double viscous_force(const BridgeLaw& law, double r_star, double gap, double gap_rate)
{
  const LiquidBridge& b = law.params;
  if (b.viscosity <= 0 || gap >= law.rupture) return 0.0;
  const double s = std::max(gap, kViscousGapFloor * r_star);
  const double shape = 1.0 - 1.0 / std::sqrt(1.0 + 2.0 * b.volume / (kPi * r_star * s * s));
  return 6.0 * kPi * b.viscosity * r_star * r_star * gap_rate / s * shape * shape;
}

double capillary_force(const LiquidBridge& b, double r_star, double gap)
{
  return capillary_force(prepare_bridge(b), r_star, gap);
}

double capillary_potential(const LiquidBridge& b, double r_star, double gap)
{
  return capillary_potential(prepare_bridge(b), r_star, gap);
}

double viscous_force(const LiquidBridge& b, double r_star, double gap, double gap_rate)
{
  return viscous_force(prepare_bridge(b), r_star, gap, gap_rate);
}

namespace
{

bool parse_number(const std::string& word, double& value)
{
  char* end = nullptr;
  value = std::strtod(word.c_str(), &end);
  return !word.empty() && end && *end == '\0' && std::isfinite(value);
}

// The keyword table of the bridge: each value keyword and where its number goes.
struct ValueKeyword {
  const char* name;
  double LiquidBridge::*field;
};
constexpr ValueKeyword kValueKeywords[] = {{"surface_tension", &LiquidBridge::surface_tension},
                                           {"contact_angle", &LiquidBridge::contact_angle},
                                           {"volume", &LiquidBridge::volume},
                                           {"viscosity", &LiquidBridge::viscosity}};
constexpr const char* kBridgeSyntax = "write 'bridge willett surface_tension G contact_angle THETA "
                                      "volume V [viscosity MU] [wet yes|no]'";

// One keyword and its value at words[k], words[k + 1]; seen counts the required ones.
std::string parse_bridge_keyword(const std::vector<std::string>& words, std::size_t k,
                                 BridgeSettings& out, int& seen)
{
  const std::string& key = words[k];
  if (k + 1 >= words.size()) return "bridge keyword '" + key + "' needs a value";
  const std::string& word = words[k + 1];
  if (key == "wet") {
    if (word != "yes" && word != "no")
      return "bridge keyword 'wet' takes yes or no, not '" + word + "'";
    out.wet = word == "yes";
    return "";
  }
  for (const ValueKeyword& v : kValueKeywords) {
    if (key != v.name) continue;
    if (!parse_number(word, out.law.*v.field))
      return "bridge keyword '" + key + "' needs a number, not '" + word + "'";
    if (key != "viscosity") ++seen;
    return "";
  }
  return "unknown bridge keyword '" + key + "'" +
         did_you_mean(key, {"surface_tension", "contact_angle", "volume", "viscosity", "wet"}) +
         "; " + kBridgeSyntax;
}

} // namespace

std::string parse_bridge_settings(const std::vector<std::string>& words, BridgeSettings& out)
{
  out = BridgeSettings{};
  if (words.empty() || words[0] != "willett")
    return "unknown bridge model '" + (words.empty() ? std::string() : words[0]) + "'" +
           (words.empty() ? std::string() : did_you_mean(words[0], {"willett"})) + "; " +
           kBridgeSyntax;
  int seen = 0;
  for (std::size_t k = 1; k < words.size(); k += 2) {
    const std::string error = parse_bridge_keyword(words, k, out, seen);
    if (!error.empty()) return error;
  }
  if (seen < 3)
    return std::string("bridge willett needs surface_tension, contact_angle and volume; ") +
           kBridgeSyntax;
  const std::string error = check_liquid_bridge(out.law);
  if (!error.empty()) return "bridge " + error;
  out.on = true;
  return "";
}

} // namespace fracdem
