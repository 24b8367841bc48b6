// Entry point that adds every fracdem style to a freshly constructed LIGGGHTS instance.
#pragma once

namespace LAMMPS_NS
{
class LAMMPS;
}

namespace fracdem
{
// Must be called after `new LAMMPS(...)` and before any input is read.
void register_styles(LAMMPS_NS::LAMMPS* lmp);
} // namespace fracdem

// C entry for ctypes users (Python): same registration on a lammps_open() handle.
extern "C" void fracdem_register_styles(void* lmp);
