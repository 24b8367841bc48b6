// pair_style fracdem/gran: host hertz + tangential history forces, then the liquid bridge pass.
#include "pair_fracdem_gran.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "atom.h"
#include "comm.h"
#include "contact_model_constants.h"
#include "error.h"
#include "fix.h"
#include "modify.h"
#include "force.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include "io/input_help.h"

using namespace LAMMPS_NS;

namespace
{

// What bridge_pair did for a pair.
constexpr int kTouching = 1, kBridged = 2;

constexpr const char* kSyntax = "write 'pair_style fracdem/gran model hertz tangential history "
                                "[bridge willett surface_tension G contact_angle THETA volume V "
                                "[viscosity MU] [wet yes|no]]'";

// error->all ends the run on every rank; it does not return.
void fail(Error* error, const std::string& what)
{
  const std::string msg = "pair_style fracdem/gran: " + what;
  error->all(FLERR, msg.c_str());
}

} // namespace

PairFracdemGran::PairFracdemGran(LAMMPS* lmp) : PairGranProxy(lmp) {}

PairFracdemGran::~PairFracdemGran()
{
  answer_as_gran(false);
}

// The host's contact-history fix (and its granular computes and fixes) find the pair style in
// their init() by the exact name "gran". Modify::init runs after the pair's init_style and
// before the neighbour lists are handed out (init_list), so the style answers to "gran" in
// between and has its own name everywhere else (restart files, messages).
void PairFracdemGran::answer_as_gran(bool on)
{
  if (on == (own_name_ != nullptr)) return;
  if (on) {
    own_name_ = force->pair_style;
    force->pair_style = new char[5];
    std::strcpy(force->pair_style, "gran");
  } else {
    delete[] force->pair_style;
    force->pair_style = own_name_;
    own_name_ = nullptr;
  }
}

// The smallest radius of the particles there are and of those the insertion fixes will make.
double PairFracdemGran::smallest_radius()
{
  double mine = std::numeric_limits<double>::infinity();
  for (int i = 0; i < atom->nlocal; ++i)
    mine = std::min(mine, atom->radius[i]);
  for (int k = 0; k < modify->nfix; ++k)
    for (int t = 1; t <= atom->ntypes; ++t) {
      const double r = modify->fix[k]->min_rad(t);
      if (r > 0) mine = std::min(mine, r);
    }
  double all = mine;
  MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE, MPI_MIN, world);
  return all;
}

void PairFracdemGran::init_style()
{
  if (bridge_.on) {
    // The host carries a pair's history across a list rebuild only for centre distances below
    // contactDistanceFactor (R_i + R_j): it must reach R_i + R_j + S_c for the smallest pair.
    const double rmin = smallest_radius();
    if (!std::isfinite(rmin))
      fail(error, "no particle and no insertion fix at the run's start, so the reach of the "
                  "bridges' history is unknown; create or insert the particles before 'run'");
    // The margin keeps the smallest pair inside the reach after the factor's round-off.
    neighbor->register_contact_dist_factor(1.0 + (1.0 + 1e-6) * law_.rupture / (2.0 * rmin));
    history_factor_ = neighbor->contactDistanceFactor;
    if (bridge_.wet && !wetted_ && update->ntimestep > 0 && comm->me == 0)
      error->warning(FLERR, "pair_style fracdem/gran: wet yes at a step > 0 bridges every pair "
                            "closer than S_c now; after read_restart write 'wet no' (the bridges "
                            "come from the restart file)");
  }
  PairGranProxy::init_style();
  answer_as_gran(true);
}

void PairFracdemGran::init_list(int id, NeighList* ptr)
{
  PairGranProxy::init_list(id, ptr);
  answer_as_gran(false);
}

// The host's words come first; only its hertz + history law is offered, and its own cohesion
// models would add a second bridge.
void PairFracdemGran::check_model_words(int narg, char** arg)
{
  if (narg < 2 || std::strcmp(arg[0], "model") != 0) fail(error, std::string("") + kSyntax);
  if (std::strcmp(arg[1], "hertz") != 0)
    fail(error, std::string("unknown model '") + arg[1] + "'" +
                    fracdem::did_you_mean(arg[1], {"hertz"}) + "; " + kSyntax);
  bool history = false;
  for (int k = 2; k < narg; k += 2) {
    const std::string key = arg[k];
    if (key == "cohesion" || key == "rolling_friction" || key == "surface" || key == "model")
      fail(error, "keyword '" + key + "' is not offered (the cohesion is the bridge); " + kSyntax);
    if (key != "tangential") continue;
    if (k + 1 >= narg || std::strcmp(arg[k + 1], "history") != 0)
      fail(error, std::string("unknown tangential model '") + (k + 1 < narg ? arg[k + 1] : "") +
                      "'; write 'tangential history'");
    history = true;
  }
  if (!history) fail(error, std::string("missing 'tangential history'; ") + kSyntax);
}

void PairFracdemGran::parse_bridge(int narg, char** arg)
{
  const std::vector<std::string> words(arg, arg + narg);
  const std::string error_text = fracdem::parse_bridge_settings(words, bridge_);
  if (!error_text.empty()) fail(error, error_text);
  law_ = fracdem::prepare_bridge(bridge_.law);
}

void PairFracdemGran::settings(int narg, char** arg)
{
  int nhost = narg;
  for (int k = 0; k < narg; ++k)
    if (std::strcmp(arg[k], "bridge") == 0) {
      nhost = k;
      break;
    }
  check_model_words(nhost, arg);
  bridge_ = fracdem::BridgeSettings{};
  if (nhost < narg) parse_bridge(narg - nhost - 1, arg + nhost + 1);
  PairGranProxy::settings(nhost, arg);
  // After the host's models have taken their history values, so theirs keep their offsets.
  if (bridge_.on) bridge_offset_ = add_history_value("fracdem_bridge", "0");
}

double PairFracdemGran::skin_to_write(double reach)
{
  const double unit = std::pow(10.0, std::floor(std::log10(reach)) - 2);
  return std::ceil(reach / unit) * unit;
}

// The paper's rule for a medium-range interaction: the buffer zone must cover its reach, or a
// list rebuild drops a bridged pair and its state.
void PairFracdemGran::init_granular()
{
  PairGranProxy::init_granular();
  if (!bridge_.on || neighbor->skin >= law_.rupture) return;
  const double skin = skin_to_write(law_.rupture);
  char msg[400];
  std::snprintf(msg, sizeof msg,
                "the bridge rupture distance (1 + theta/2) V^(1/3) = %.6g exceeds the neighbour "
                "skin %.6g, so a list rebuild would lose bridges; write 'neighbor %.3g bin' or "
                "more",
                law_.rupture, neighbor->skin, skin);
  fail(error, msg);
}

void PairFracdemGran::write_restart_settings(FILE* fp)
{
  PairGranProxy::write_restart_settings(fp);
  const int flags[3] = {bridge_.on, bridge_.wet, wetted_};
  const fracdem::LiquidBridge& b = bridge_.law;
  const double law[4] = {b.surface_tension, b.contact_angle, b.volume, b.viscosity};
  std::fwrite(flags, sizeof(int), 3, fp);
  std::fwrite(law, sizeof(double), 4, fp);
}

void PairFracdemGran::read_restart_settings(FILE* fp, const int major, const int minor)
{
  PairGranProxy::read_restart_settings(fp, major, minor);
  int flags[3] = {0, 0, 0};
  double law[4] = {0, 0, 0, 0};
  if (comm->me == 0 &&
      (std::fread(flags, sizeof(int), 3, fp) != 3 || std::fread(law, sizeof(double), 4, fp) != 4))
    error->one(FLERR, "pair_style fracdem/gran: restart file ends inside the bridge settings");
  MPI_Bcast(flags, 3, MPI_INT, 0, world);
  MPI_Bcast(law, 4, MPI_DOUBLE, 0, world);
  bridge_.on = flags[0];
  bridge_.wet = flags[1];
  wetted_ = flags[2];
  bridge_.law = fracdem::LiquidBridge{law[0], law[1], law[2], law[3]};
  law_ = fracdem::prepare_bridge(bridge_.law);
  if (bridge_.on) bridge_offset_ = add_history_value("fracdem_bridge", "0");
}

void PairFracdemGran::compute_force(int eflag, int vflag, int addflag)
{
  PairGranProxy::compute_force(eflag, vflag, addflag);
  // compute pair/gran/local recomputes with computeflag 0: forces and states stay as they are.
  if (!computeflag()) return;
  const bool counting = count_next_ || update->setupflag;
  if (counting) start_counts();
  if (bridge_.on)
    bridge_pass(counting);
  else if (counting)
    count_pass();
  count_next_ = false;
}

void PairFracdemGran::start_counts()
{
  const int n = atom->nlocal;
  counts_.contacts.assign(n, 0);
  counts_.bridges.assign(n, 0);
  counts_.idle.assign(n, 0);
  counts_.step = update->ntimestep;
}

// Without bridges: the host's contact test (centre distance below the radii's sum) per pair.
void PairFracdemGran::count_pass()
{
  double** x = atom->x;
  const double* radius = atom->radius;
  const int nlocal = atom->nlocal;
  for (int ii = 0; ii < list->inum; ++ii) {
    const int i = list->ilist[ii];
    if (i >= nlocal) continue;
    const int* jlist = list->firstneigh[i];
    for (int jj = 0; jj < list->numneigh[i]; ++jj) {
      const int j = jlist[jj] & NEIGHMASK;
      const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
      const double rs = radius[i] + radius[j];
      const bool touching = dx * dx + dy * dy + dz * dz < rs * rs;
      counts_.contacts[i] += touching;
      counts_.idle[i] += !touching;
    }
  }
}

void PairFracdemGran::bridge_pass(bool counting)
{
  const bool wet_now = bridge_.wet && !wetted_;
  if (wet_now) {
    // Wetting waits for the first particles (insertion may come after the first set-up).
    int mine = list->inum > 0, any = 0;
    MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, world);
    wetted_ = any != 0;
  }
  int** first_flag = listgranhistory->firstneigh;
  double** first_hist = listgranhistory->firstdouble;
  const int nd = dnum();
  const int nlocal = atom->nlocal;
  for (int ii = 0; ii < list->inum; ++ii) {
    const int i = list->ilist[ii];
    const int* jlist = list->firstneigh[i];
    for (int jj = 0; jj < list->numneigh[i]; ++jj) {
      const int did = bridge_pair(i, jlist[jj] & NEIGHMASK, first_hist[i][nd * jj + bridge_offset_],
                                  &first_flag[i][jj], wet_now);
      if (!counting || i >= nlocal) continue;
      counts_.contacts[i] += did & kTouching;
      counts_.bridges[i] += (did & kBridged) != 0;
      counts_.idle[i] += did == 0;
    }
  }
}

// One pair: update its bridge state, then apply the bridge's normal force (attractive > 0) and
// tally its potential and virial as the host tallies contact forces. Returns what the pair did:
// kTouching (the host's contact law ran) and kBridged bits.
int PairFracdemGran::bridge_pair(int i, int j, double& state, int* contact_flag, bool wet_now)
{
  using LIGGGHTS::ContactModels::CONTACT_COHESION_MODEL;
  double** x = atom->x;
  double** v = atom->v;
  const double* radius = atom->radius;
  const double del[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
  const double rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
  const double radsum = radius[i] + radius[j];
  // Most listed pairs have never touched: no bridge, and no square root to learn it.
  if (state < 0.5 && !wet_now && rsq > radsum * radsum) {
    *contact_flag &= ~CONTACT_COHESION_MODEL;
    return 0;
  }
  const int touching = rsq < radsum * radsum ? kTouching : 0;
  const double r = std::sqrt(rsq);
  const double gap = r - radsum;
  const bool was = state > 0.5 || (wet_now && gap < law_.rupture);
  const bool now = fracdem::bridge_persists(was, gap, law_.rupture);
  state = now ? 1.0 : 0.0;
  // The flag keeps the pair's history through exchange and rebuilds while the bridge lasts.
  if (!now) {
    *contact_flag &= ~CONTACT_COHESION_MODEL;
    return touching;
  }
  *contact_flag |= CONTACT_COHESION_MODEL;
  if (radsum * (history_factor_ - 1.0) < law_.rupture)
    error->one(FLERR, "pair_style fracdem/gran: a bridged pair smaller than the smallest particles "
                      "at the run's start (radii changed, or inserted smaller); its bridge would "
                      "not survive a list rebuild: start a new run after the change");
  const double en[3] = {del[0] / r, del[1] / r, del[2] / r};
  const double rate = (v[i][0] - v[j][0]) * en[0] + (v[i][1] - v[j][1]) * en[1] +
                      (v[i][2] - v[j][2]) * en[2]; // dS/dt
  const double rs = fracdem::derjaguin_radius(radius[i], radius[j]);
  const double fn =
      fracdem::capillary_force(law_, rs, gap) + fracdem::viscous_force(law_, rs, gap, rate);
  const double fi[3] = {-fn * en[0], -fn * en[1], -fn * en[2]};
  double** f = atom->f;
  const int nlocal = atom->nlocal;
  const int newton_pair = force->newton_pair;
  for (int d = 0; d < 3; ++d)
    f[i][d] += fi[d];
  if (newton_pair || j < nlocal)
    for (int d = 0; d < 3; ++d)
      f[j][d] -= fi[d];
  if (evflag) {
    const double u = eflag_either ? fracdem::capillary_potential(law_, rs, gap) : 0.0;
    ev_tally_xyz(i, j, nlocal, newton_pair, u, 0.0, fi[0], fi[1], fi[2], del[0], del[1], del[2]);
  }
  return touching | kBridged;
}
