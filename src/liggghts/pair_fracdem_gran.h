// pair_style fracdem/gran: the host's granular pair style (hertz, tangential history) plus an
// optional liquid bridge (core/contact/liquid_bridge) between particles.
#pragma once

#include <vector>

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

  // What one step's pair work did for each local particle, counted where it is done: contacts
  // (touching pairs: the contact law ran), bridges (the bridge force ran; a bridged pair in
  // contact is both) and idle pairs (listed, neither). A pair is counted for the particle whose
  // neighbour list holds it, as a recount over the list does. step: the step counted (-1: none).
  struct WorkCounts {
    std::vector<int> contacts, bridges, idle;
    bigint step = -1;
  };
  // Counting costs a pass over the list without bridges (with bridges it rides on the bridge
  // pass), so it is done at the set-up's force computation and at the next one after a request.
  void request_counts() { count_next_ = true; }
  const WorkCounts& work_counts() const { return counts_; }

private:
  void check_model_words(int narg, char** arg);
  void parse_bridge(int narg, char** arg);
  void bridge_pass(bool counting);
  int bridge_pair(int i, int j, double& state, int* contact_flag, bool wet_now);
  void count_pass();
  void start_counts();

  void answer_as_gran(bool on);
  double smallest_radius();

  fracdem::BridgeSettings bridge_;
  char* own_name_ = nullptr;  // force->pair_style while it answers to "gran"
  fracdem::BridgeLaw law_;    // bridge_.law prepared, with its rupture distance S_c
  double history_factor_ = 1; // the host's contactDistanceFactor this run
  int bridge_offset_ = -1;    // index of the bridge state in a pair's contact history
  bool wetted_ = false;       // wet yes bridges close pairs once, when particles first exist
  WorkCounts counts_;
  bool count_next_ = false;
};

} // namespace LAMMPS_NS
