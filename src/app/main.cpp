// The fracdem executable: stock LIGGGHTS main plus one call that registers the plugin styles.
#include <mpi.h>

#include <csignal>
#include <cstring>

#include "input.h"
#include "lammps.h"
#include "register_styles.h"
#include "signal_handling.h"

using namespace LAMMPS_NS;

int main(int argc, char** argv)
{
  // Same signal behaviour as the stock `liggghts` binary (graceful quit/restart).
  struct sigaction int_action, usr1_action;
  std::memset(&int_action, 0, sizeof(int_action));
  std::memset(&usr1_action, 0, sizeof(usr1_action));
  int_action.sa_handler = SignalHandler::int_handler;
  sigaction(SIGINT, &int_action, nullptr);
  sigaction(SIGTERM, &int_action, nullptr);
  usr1_action.sa_handler = SignalHandler::usr1_handler;
  sigaction(SIGUSR1, &usr1_action, nullptr);

  MPI_Init(&argc, &argv);
  LAMMPS* lammps = new LAMMPS(argc, argv, MPI_COMM_WORLD);
  fracdem::register_styles(lammps);
  lammps->input->file();
  delete lammps;
  MPI_Finalize();
  return 0;
}
