// The contact between the replicated bodies of a run (contact_bodies yes): one owner of their
// scene, its members, and the contacts carried from one run into the next and through restart.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "contact/contact_scene.h"
#include "contact/edge_contact.h"
#include "contact/surface_contact.h"
#include "fem/body.h"

namespace fracdem
{

// What a body lends the scene (BodyDriver::scene_member).
struct SceneBody {
  std::string id;
  ContactSurface* surface = nullptr;
  SurfaceContact* self = nullptr;
  EdgeContact* edges = nullptr; // null without contact_edges
  Body* body = nullptr;
  int surface_type = 0;
  double youngs = 0;
  // The settings of its pair with a body of (type, Young's modulus) at this friction, and its
  // friction between two surface types (set by its own set-up, which may come after the scene's).
  std::function<SurfaceContactOptions(int, double, double)> options;
  const std::function<double(int, int)>* friction = nullptr;
  const bool* contacts_held = nullptr;     // it holds the contact forces of the last evaluation
  std::vector<double>* restored = nullptr; // pair records of its restart file, until taken
};

// The scene of the members, in the host's order (first to last). Every member holds the
// coordinator; the first member's set-up of a run makes it (ContactCoordinator::renew), the
// scene is configured at the run's first evaluation, when every member has set up.
class ContactCoordinator
{
public:
  // How the scene reports and fails (the first member's host and contact_balance keyword).
  struct Settings {
    ContactBalance balance;
    SceneComm comm;
    std::function<void(const std::string&)> fail; // must not return
    std::function<void(const std::string&)> print;
  };

  // The coordinator of `members` for a new run: `last` (the previous run's, or null) goes on
  // where it held the same members (their pairs' contacts carried into the new scene), else the
  // pair records restored from the members' restart files are taken where they hold every pair.
  static std::shared_ptr<ContactCoordinator> renew(const std::shared_ptr<ContactCoordinator>& last,
                                                   const std::vector<const void*>& keys,
                                                   std::vector<SceneBody> members,
                                                   Settings settings);

  // A member left (unfix): the scene is disbanded until the next run's set-up.
  void disband();
  bool active() const { return scene_ != nullptr; }
  int size() const { return static_cast<int>(members_.size()); }
  int index_of(const void* key) const;

  // Configures the scene at the first evaluation of a run.
  void configure_if_pending();
  // Evaluates the pieces of member k and its pairs with later members (forces into their
  // pending arrays).
  int evaluate(int k, std::int64_t step, double dt);
  void invalidate();
  // Gathers member k's own-piece contacts spread over the ranks (restart, a new run).
  void gather_self_state(int k);
  // Whether the members' held contact forces replay at a run's set-up: only where they are the
  // last run's members and their pairs go on, and all of them hold forces.
  bool replays() const;
  // The pair records of the scene, for the first member's restart record (every rank enters).
  std::vector<double> pair_records() const;
  const ContactScene* scene() const { return scene_.get(); }

private:
  std::vector<double> scene_pair_records() const;
  void take_restored_pairs();
  void restore_pairs();
  void drop_restored_pairs();

  std::unique_ptr<ContactScene> scene_;
  std::vector<const void*> keys_; // the members' identities, to compare runs
  std::vector<SceneBody> members_;
  Settings settings_;
  bool pending_ = false;
  bool continues_ = false;             // its members are those of the last run
  std::vector<double> carried_;        // their pairs' contacts (records), for the new scene
};

} // namespace fracdem
