// fix fem/vtk under LAMMPS: finds the fem/body fix and writes the core's BodyFields each N steps.
#include "fix_fem_vtk_lammps.h"

#include <exception>
#include <vector>

#include "comm.h"
#include "error.h"
#include "modify.h"
#include "update.h"

#include "fix_fem_body_lammps.h"
#include "body/body_fields.h"
#include "io/vtk_writer.h"

using namespace LAMMPS_NS;
using namespace FixConst;

FixFemVtkLammps::FixFemVtkLammps(LAMMPS* lmp, int narg, char** arg) : Fix(lmp, narg, arg)
{
  const std::vector<std::string> words(arg + 3, arg + narg);
  fracdem::VtkFixArgs a;
  const std::string err = fracdem::parse_vtk_fix_args(words, a);
  if (!err.empty()) error->all(FLERR, err);
  if (a.nevery > MAXSMALLINT) error->all(FLERR, "fix fem/vtk: output interval N is too large");
  nevery = static_cast<int>(a.nevery);
  prefix_ = a.prefix;
  body_id_ = a.body_id;
  series_ = std::make_unique<fracdem::PvdSeries>(prefix_ + ".pvd");
}

FixFemVtkLammps::~FixFemVtkLammps() = default;

int FixFemVtkLammps::setmask()
{
  return END_OF_STEP;
}

// Looked up at every init: the body fix may be defined after this one, or redefined between runs.
void FixFemVtkLammps::init()
{
  const Fix* f = modify->get_fix_by_id(body_id_);
  body_ = dynamic_cast<const FixFemBodyLammps*>(f);
  if (!body_) error->all(FLERR, fracdem::vtk_body_fix_error(body_id_, f ? f->style : ""));
}

void FixFemVtkLammps::setup(int)
{
  if (update->ntimestep % nevery == 0) write_frame();
}

void FixFemVtkLammps::end_of_step()
{
  write_frame();
}

void FixFemVtkLammps::write_frame()
{
  if (update->ntimestep == last_written_) return;
  last_written_ = update->ntimestep;
  const double time = update->atime + (update->ntimestep - update->atimestep) * update->dt;
  try {
    fracdem::write_body_frame(prefix_, update->ntimestep, time, comm->me, comm->nprocs,
                              body_->body(), body_->distributed() ? &body_->part() : nullptr,
                              *series_, body_->distributed() ? &body_->topology() : nullptr);
  } catch (const std::exception& e) {
    error->one(FLERR, std::string("fix fem/vtk: ") + e.what());
  }
}
