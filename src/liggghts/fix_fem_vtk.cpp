// fix fem/vtk: a fem/body's displacement, velocity, stress and material state for ParaView.
#include "fix_fem_vtk.h"

#include <cstring>
#include <exception>
#include <vector>

#include "comm.h"
#include "error.h"
#include "modify.h"
#include "update.h"

#include "fix_fem_body.h"
#include "body/body_fields.h"
#include "io/vtk_writer.h"

using namespace LAMMPS_NS;
using namespace FixConst;

// fix ID group fem/vtk N PREFIX body BODY_FIX_ID; the fields are the core's fracdem::BodyFields,
// which the LAMMPS adapter (src/lammps/fix_fem_vtk_lammps.cpp) writes too.
FixFemVtk::FixFemVtk(LAMMPS* lmp, int narg, char** arg) : Fix(lmp, narg, arg)
{
  const std::vector<std::string> words(arg + 3, arg + narg);
  fracdem::VtkFixArgs a;
  const std::string err = fracdem::parse_vtk_fix_args(words, a);
  if (!err.empty()) error->all(FLERR, err.c_str());
  if (a.nevery > MAXSMALLINT) error->all(FLERR, "fix fem/vtk: output interval N is too large");
  nevery = static_cast<int>(a.nevery);
  prefix_ = a.prefix;
  body_id_ = a.body_id;
  series_ = std::make_unique<fracdem::PvdSeries>(prefix_ + ".pvd");
}

FixFemVtk::~FixFemVtk() = default;

int FixFemVtk::setmask()
{
  return END_OF_STEP;
}

void FixFemVtk::init()
{
  Fix* f = modify->find_fix_id(body_id_.c_str());
  if (!f || strcmp(f->style, "fem/body") != 0) {
    const std::string msg = fracdem::vtk_body_fix_error(body_id_, f ? f->style : "");
    error->all(FLERR, msg.c_str());
  }
  body_ = static_cast<FixFemBody*>(f);
}

void FixFemVtk::setup(int)
{
  if (update->ntimestep % nevery == 0) write_frame();
}

void FixFemVtk::end_of_step()
{
  write_frame();
}

void FixFemVtk::write_frame()
{
  if (update->ntimestep == last_written_) return;
  last_written_ = update->ntimestep;
  const double time = update->atime + (update->ntimestep - update->atimestep) * update->dt;
  try {
    fracdem::write_body_frame(prefix_, update->ntimestep, time, comm->me, comm->nprocs,
                              body_->body(), body_->distributed() ? &body_->part() : nullptr,
                              *series_, body_->distributed() ? &body_->topology() : nullptr);
  } catch (const std::exception& e) {
    const std::string msg = std::string("fix fem/vtk: ") + e.what();
    error->one(FLERR, msg.c_str());
  }
}
