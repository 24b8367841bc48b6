// fix fracdem/skin: tunes the neighbour skin during a run towards the least measured time per
// step (the search in src/core/balance/skin_search), rebuilding the lists with each new skin.
#pragma once

#include <memory>

#include "balance/skin_search.h"
#include "fix.h"

namespace LAMMPS_NS
{

class FixFracdemSkin : public Fix
{
public:
  FixFracdemSkin(class LAMMPS*, int, char**);
  ~FixFracdemSkin() override;

  int setmask() override;
  void init() override;
  void setup(int) override;
  void end_of_step() override;
  void pre_exchange() override;
  double compute_scalar() override;
  double compute_vector(int) override;
  void write_restart(FILE*) override;
  void restart(char*) override;

private:
  void fail(const std::string& msg) const;
  void check_bridges() const;
  void check_order() const;
  bool meshes_on_ranks() const;
  double measured_seconds() const;
  void apply_skin(double skin);

  fracdem::balance::SkinSearchSettings settings_;
  std::unique_ptr<fracdem::balance::SkinSearch> search_;
  double pending_ = -1;     // skin to take at the next list rebuild (< 0: none)
  double restored_ = -1;    // skin read from a restart file, taken at the first init
  bool wall_clock_ = false; // clock wall: the host's timers; clock cpu: the process's CPU time
  double seconds_last_ = 0; // measured seconds at the interval's start
  bigint step_last_ = 0;    // its step
  bool run_start_ = false;  // the host zeroes its timers after set-up
  double last_cost_ = 0;    // the last interval's seconds per step
  int changes_ = 0;
};

} // namespace LAMMPS_NS
