// fix fem/vtk under LAMMPS: periodic ParaView output (.vtu + .pvd) of a fix fem/body's state.
#pragma once

#include <memory>
#include <string>

#include "fix.h"

namespace fracdem
{
class PvdSeries;
}

namespace LAMMPS_NS
{

class FixFemBodyLammps;

// fix ID group fem/vtk N PREFIX body BODY_FIX_ID, as under LIGGGHTS (docs/fix_fem_vtk.md): the
// fields come from the core's fracdem::BodyFields, so both hosts write the same files.
class FixFemVtkLammps : public Fix
{
public:
  FixFemVtkLammps(class LAMMPS*, int, char**);
  ~FixFemVtkLammps() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void end_of_step() override;

private:
  void write_frame();
  std::string prefix_;
  std::string body_id_;
  const FixFemBodyLammps* body_ = nullptr;
  std::unique_ptr<fracdem::PvdSeries> series_;
  bigint last_written_ = -1;
};

} // namespace LAMMPS_NS
