// compute fracdem/cost under LAMMPS: each particle's a posteriori cost (the paper's work model,
// section 5.1) recorded over the steps since the last balance check, as a per-atom vector for
// LAMMPS's own `fix balance ... weight var` / `balance ... weight var`.
//
// The recording lives in an internal fix (style FRACDEM/COST, created by the compute), so that
// the per-atom sums migrate with their atoms (exchange, sort) like any fix's per-atom array.
#pragma once

#include <string>
#include <vector>

#include "balance/cost_model.h"
#include "compute.h"
#include "fix.h"

namespace LAMMPS_NS
{

class FixFemBodyLammps;

// Internal: records, at the end of every step, what the step did for each particle and adds its
// cost to the particle's sums. Not meant to be used directly (compute fracdem/cost creates it).
class FixFracdemCost : public Fix
{
public:
  FixFracdemCost(class LAMMPS*, int, char**);
  ~FixFracdemCost() override;

  int setmask() override;
  void init() override;
  void init_list(int, class NeighList*) override;
  void setup(int) override;
  void end_of_step() override;

  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double*) override;
  int unpack_exchange(int, double*) override;
  int pack_reverse_comm(int, int, double*) override;
  void unpack_reverse_comm(int, int*, double*) override;
  double memory_usage() override;

  // The relative cost of each recorded item (the compute's keywords: base = particle, check =
  // pair_check, pair = sphere_contact, facet_check, facet = facet_contact; walls are not recorded).
  fracdem::balance::InteractionCosts weights;
  bigint window = 0; // the sums restart at steps that are multiples of this (0: never)

  // Mean cost per recorded step of local atom i (the base cost when nothing was recorded).
  double mean_cost(int i) const;
  // This rank's summed particle cost and number of steps: in the current window, in the run.
  double window_work = 0, run_work = 0;
  bigint window_steps = 0, run_steps = 0;

private:
  void record();

  class NeighList* list_ = nullptr;
  std::vector<FixFemBodyLammps*> bodies_;
  double** sums_ = nullptr; // per atom: summed cost, recorded steps
  std::vector<double> step_cost_;
  bigint window_start_ = -1;
};

class ComputeFracdemCost : public Compute
{
public:
  ComputeFracdemCost(class LAMMPS*, int, char**);
  ~ComputeFracdemCost() override;

  void init() override;
  void compute_peratom() override;
  void compute_vector() override;
  double memory_usage() override;

private:
  double number(const char* keyword, const char* word);
  int parse_costs(int iarg, int narg, char** arg, bool given[]);

  std::string id_fix_;
  FixFracdemCost* fix_ = nullptr;
  fracdem::balance::InteractionCosts weights_;
  bigint every_ = -1; // -1: the Nevery of the first fix balance, else no reset
  int nmax_ = 0;
  double* cost_ = nullptr;
};

} // namespace LAMMPS_NS
