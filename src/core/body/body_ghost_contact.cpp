// BodyDriver's particle contact with a distributed body: boxes when the host re-neighbours, facet
// ghosts to the ranks whose particles can reach them and the forces back, each step.
#include "body/body_driver.h"

namespace fracdem
{

// Particles keep the host's decomposition, the body its own (paper section 3). After the host
// re-neighbours every rank gathers every rank's particle box and surface box (12 doubles each,
// the only collective); each step every part sends the facets within reach of each partner's
// particles (one message per partner), the partner evaluates its particles against them and its
// own facets and returns the nodes' forces (one message back), and the shared-node sum
// (distributed_forces, after the pieces' contact too) gives every sharer the total once.
void BodyDriver::distributed_contact(const ParticleArrays& p, std::int64_t step, double dt)
{
  const double* x = body_.positions().data();
  const double* v = body_.velocities().data();
  if (boxes_due_) {
    ghosts_.set_boxes(host_.all_gather(ghosts_.local_boxes(p, x)));
    boxes_due_ = false;
  }
  std::string why = ghosts_.check_particles(p);
  const double* mass = contact_masses();
  const std::vector<char>* inelastic = mark_inelastic_nodes();
  if (why.empty()) why = ghosts_.outgoing(x, v, ghost_out_, mass, inelastic);
  if (!why.empty()) fail_one(prefix() + why);
  host_.exchange(0, ghosts_.send_to(), ghost_out_, ghosts_.recv_from(), ghost_in_);
  const ParticleFacetResult res =
      ghosts_.evaluate(p, ghost_in_, x, v, dt, body_.contact_forces(), ghost_back_, mass, inelastic);
  host_.exchange(1, ghosts_.recv_from(), ghost_back_, ghosts_.send_to(), ghost_returned_);
  ghosts_.add_returned(ghost_returned_, body_.contact_forces()); // summed by the caller
  ncontacts_ = res.contacts;
  // Warnings come from the rank that sees the case (no collective per step).
  warn_history_slots(res);
  if (res.patch_radii > kPatchRadii && !warned_patch_) {
    warned_patch_ = true;
    host_.warning(wide_patch_text(step, res.patch_radii));
  }
  if (res.unresolved_speed > 0 && !warned_unresolved_) {
    warned_unresolved_ = true;
    host_.warning(unresolved_contact_text(step, res.unresolved_speed, res.resolving_dt));
  }
}

} // namespace fracdem
