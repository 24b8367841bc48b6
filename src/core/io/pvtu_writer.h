// Parallel frames for ParaView: the .pvtu index that joins the ranks' .vtu pieces of one step.
#pragma once

#include <string>
#include <vector>

#include "io/vtk_writer.h"

namespace fracdem
{

// Writes the index of one frame written in pieces (one write_vtu per rank, all with the same
// `fields`): the arrays every piece holds (element_id and region as write_vtu adds them, then
// `fields`; their data pointers are not read) and the pieces, named relative to the .pvtu's
// directory. Atomic like write_vtu (temporary file, rename). Throws std::invalid_argument for no
// pieces or a reserved / repeated field name, std::runtime_error naming the path when the file
// cannot be written.
void write_pvtu(const std::string& path, const std::vector<std::string>& piece_paths,
                const std::vector<VtkField>& fields);

} // namespace fracdem
