// pair_style fracdem/gran: the host's granular pair style (hertz, tangential history) plus an
// optional liquid bridge (core/contact/liquid_bridge) between particles.
#pragma once

#include "pair_gran_proxy.h"

#include "contact/liquid_bridge.h"

namespace LAMMPS_NS
{

// The contact forces are the host's own PairGranProxy with the same model words, so without a
// bridge the style is pair gran; the bridge is a second pass over the same neighbour list whose
// state (bridged or not) is one value of each pair's contact history, kept by the host's
// contact-history fix through exchange, neighbour rebuilds and restart.
class PairFracdemGran : public PairGranProxy
{
public:
  explicit PairFracdemGran(LAMMPS* lmp);

  ~PairFracdemGran() override;

  void settings(int narg, char** arg) override;
  void init_style() override;
  void init_list(int id, NeighList* ptr) override;
  void init_granular() override;
  void write_restart_settings(FILE* fp) override;
  void read_restart_settings(FILE* fp, const int major, const int minor) override;
  void compute_force(int eflag, int vflag, int addflag) override;

  // The bridges' rupture distance S_c, the least skin that keeps them (0 without bridges).
  double bridge_reach() const { return bridge_.on ? law_.rupture : 0.0; }
  // The skin written in the refusal of a skin below bridge_reach(): S_c rounded up to three
  // significant digits, so that the value written passes the check.
  static double skin_to_write(double reach);

private:
  void check_model_words(int narg, char** arg);
  void parse_bridge(int narg, char** arg);
  void bridge_pass();
  void bridge_pair(int i, int j, double& state, int* contact_flag, bool wet_now);

  void answer_as_gran(bool on);
  double smallest_radius();

  fracdem::BridgeSettings bridge_;
  char* own_name_ = nullptr;  // force->pair_style while it answers to "gran"
  fracdem::BridgeLaw law_;    // bridge_.law prepared, with its rupture distance S_c
  double history_factor_ = 1; // the host's contactDistanceFactor this run
  int bridge_offset_ = -1;    // index of the bridge state in a pair's contact history
  bool wetted_ = false;       // wet yes bridges close pairs once, when particles first exist
};

} // namespace LAMMPS_NS
