// The one place where fracdem styles enter the host's style maps.
#include "register_styles.h"

#include <map>
#include <string>

#include "fix.h"
#include "force.h"
#include "lammps.h"
#include "modify.h"
#include "comm.h"

#include "comm_graph.h"
#include "fix_balance_graph.h"
#include "fix_fem_body.h"
#include "fix_fem_vtk.h"
#include "fix_fracdem_skin.h"
#include "pair_fracdem_gran.h"

using namespace LAMMPS_NS;

namespace
{

// LIGGGHTS 3.8 keeps Modify::fix_map private and has no plugin loader. The
// explicit-instantiation access idiom is the standard-conforming way to name a
// private member: explicit instantiations may refer to private members, and
// the friend function defined in the instantiated template hands out the
// member pointer.
using FixCreatorFn = Fix* (*)(LAMMPS*, int, char**);
using FixMap = std::map<std::string, FixCreatorFn>;

struct ModifyFixMapTag {
  using type = FixMap* Modify::*;
  friend type member_of(ModifyFixMapTag);
};

template <typename Tag, typename Tag::type Member> struct PrivateMemberAccess {
  friend typename Tag::type member_of(Tag) { return Member; }
};
template struct PrivateMemberAccess<ModifyFixMapTag, &Modify::fix_map>;

template <typename T> Fix* create_fix(LAMMPS* lmp, int narg, char** arg)
{
  return new T(lmp, narg, arg);
}

template <typename T> Pair* create_pair(LAMMPS* lmp)
{
  return new T(lmp);
}

} // namespace

namespace fracdem
{

void register_styles(LAMMPS* lmp)
{
  FixMap& fix_map = *(lmp->modify->*member_of(ModifyFixMapTag{}));
  fix_map["balance/graph"] = &create_fix<FixBalanceGraph>;
  fix_map["fem/body"] = &create_fix<FixFemBody>;
  // The graph-ownership communicator behaves as the stock Comm until fix balance/graph switches
  // it on; it must be in place before the input sets the processor grid.
  if (!dynamic_cast<CommGraph*>(lmp->comm)) {
    delete lmp->comm;
    lmp->comm = new CommGraph(lmp);
  }
  fix_map["fem/vtk"] = &create_fix<FixFemVtk>;
  fix_map["fracdem/skin"] = &create_fix<FixFracdemSkin>;
  // Force::pair_map is public in LIGGGHTS 3.8.
  (*lmp->force->pair_map)["fracdem/gran"] = &create_pair<PairFracdemGran>;
}

} // namespace fracdem

extern "C" void fracdem_register_styles(void* lmp)
{
  fracdem::register_styles(static_cast<LAMMPS*>(lmp));
}
