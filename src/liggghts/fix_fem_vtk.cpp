// fix fem/vtk: a fem/body's displacement, velocity, stress and material state for ParaView.
#include "fix_fem_vtk.h"

#include <cstring>
#include <stdexcept>
#include <vector>

#include "comm.h"
#include "error.h"
#include "force.h"
#include "modify.h"
#include "update.h"

#include "fix_fem_body.h"
#include "fem/node_split.h"
#include "materials/material_table.h"
#include "io/vtk_writer.h"

using namespace LAMMPS_NS;
using namespace FixConst;

// fix ID group fem/vtk N PREFIX body BODY_FIX_ID
namespace
{
// Per element: damage (0 intact .. 1 no tension left), crack normal, fragment id; per node:
// 1 where a crack runs through the node (split nodes and their copies).
void fracture_fields(const fracdem::Body& body, std::vector<double>& damage,
                     std::vector<double>& normal, std::vector<double>& fragment,
                     std::vector<double>& split, std::vector<fracdem::VtkField>& fields)
{
  const fracdem::Mesh& mesh = body.mesh();
  const int ne = mesh.num_elems(), nn = mesh.num_nodes();
  damage.assign(ne, 0.0);
  normal.assign(3 * ne, 0.0);
  for (int e = 0; e < ne; ++e)
    damage[e] = body.element_failure(e, &normal[3 * e]);
  std::vector<int> comp;
  fracdem::element_components(mesh, comp);
  fragment.assign(comp.begin(), comp.end());
  split.assign(nn, 0.0);
  for (int n = 0; n < nn; ++n)
    if (body.parents()[n] >= 0) split[n] = split[body.parents()[n]] = 1.0;
  fields.push_back({"damage", 1, damage.data(), true});
  fields.push_back({"crack_normal", 3, normal.data(), true});
  fields.push_back({"fragment", 1, fragment.data(), true});
  fields.push_back({"split", 1, split.data(), false});
}
} // namespace

FixFemVtk::FixFemVtk(LAMMPS* lmp, int narg, char** arg) : Fix(lmp, narg, arg)
{
  if (narg != 7 || strcmp(arg[5], "body") != 0)
    error->all(FLERR, "fix fem/vtk: expected 'fix ID group fem/vtk N PREFIX body BODY_FIX_ID'");
  nevery = force->inumeric(FLERR, arg[3]);
  if (nevery <= 0) error->all(FLERR, "fix fem/vtk: output interval N must be > 0");
  prefix_ = arg[4];
  body_id_ = arg[6];
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
    std::string msg = "fix fem/vtk: keyword 'body': no fix fem/body with ID '" + body_id_ + "'";
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
  // The body is replicated: rank 0 writes, others only need the stresses if
  // they were distributed (they are not).
  if (comm->me != 0) return;

  const fracdem::Mesh& mesh = body_->mesh();
  const auto& x = body_->positions();
  const auto& v = body_->velocities();
  const int nn = mesh.num_nodes(), ne = mesh.num_elems();
  std::vector<double> disp(3 * nn);
  for (int k = 0; k < 3 * nn; ++k)
    disp[k] = x[k] - mesh.X[k];
  std::vector<double> stress(6 * ne, 0.0), mises(ne, 0.0), energy_density(ne, 0.0);
  const fracdem::Body& body = body_->body();
  if (!body.rigid()) {
    std::vector<double> elem_energy;
    body.element_energies(elem_energy);
    for (int e = 0; e < ne; ++e) {
      if (!mesh.active[e]) continue;
      body.element_stress(e, &stress[6 * e]);
      mises[e] = fracdem::FeSpace::von_mises(&stress[6 * e]);
      const double vol = body_->fe_space().reference_measure(e);
      energy_density[e] = vol > 0 ? elem_energy[e] / vol : 0.0;
    }
  }
  std::vector<fracdem::VtkField> fields = {
      {"displacement", 3, disp.data(), false},
      {"velocity", 3, v.data(), false},
      {"stress", 6, stress.data(), true},
      {"von_mises", 1, mises.data(), true},
      {"strain_energy_density", 1, energy_density.data(), true},
  };
  // Fracture fields only for materials that fail (elastic output stays as it was).
  std::vector<double> damage, normal, fragment, split;
  if (fracdem::material_model_info(body.material().model).fractures)
    fracture_fields(body, damage, normal, fragment, split, fields);
  // Plastic state only for plastic materials (element means over the integration points).
  std::vector<double> eps_bar, temperature_rise, plastic_work;
  if (body.element_plastic_state(eps_bar, temperature_rise, plastic_work)) {
    fields.push_back({"plastic_strain", 1, eps_bar.data(), true});
    fields.push_back({"temperature_rise", 1, temperature_rise.data(), true});
    fields.push_back({"plastic_work", 1, plastic_work.data(), true});
  }
  char name[64];
  snprintf(name, sizeof(name), "_%010lld.vtu", static_cast<long long>(update->ntimestep));
  const std::string path = prefix_ + name;
  try {
    fracdem::write_vtu(path, mesh, x.data(), fields);
    series_->add(update->atime + (update->ntimestep - update->atimestep) * update->dt, path);
  } catch (const std::exception& e) {
    std::string msg = std::string("fix fem/vtk: ") + e.what();
    error->one(FLERR, msg.c_str());
  }
}
