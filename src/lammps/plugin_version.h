// The LAMMPS version check of fracdemplugin.so, on its own so that it is testable without a host.
#pragma once

#include <string>

namespace fracdem
{

// A plugin is compiled against one LAMMPS's headers; class layouts (Fix, Atom, Modify) change
// between versions, so loading it into another LAMMPS would corrupt memory rather than fail.
// Returns "" when the host's version string equals the expected one, otherwise the message
// that refuses the load, naming both versions.
inline std::string lammps_version_mismatch(const std::string& host, const std::string& expected)
{
  if (host == expected) return "";
  return "fracdemplugin.so was built for LAMMPS version '" + expected +
         "' but is being loaded into LAMMPS version '" + host +
         "'; no fracdem style was registered (rebuild the plugin against this LAMMPS: "
         "scripts/setup_lammps.sh)";
}

} // namespace fracdem
