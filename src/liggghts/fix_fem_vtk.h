// fix fem/vtk: periodic ParaView (VTK XML .vtu + .pvd) output of a fem/body's current state.
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

class FixFemVtk : public Fix
{
public:
  FixFemVtk(class LAMMPS*, int, char**);
  ~FixFemVtk() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void end_of_step() override;

private:
  void write_frame();
  std::string prefix_;
  std::string body_id_;
  class FixFemBody* body_ = nullptr;
  std::unique_ptr<fracdem::PvdSeries> series_;
  bigint last_written_ = -1;
};

} // namespace LAMMPS_NS
