// Gmsh .msh (ASCII 2.2 / 4.1) reader and 2.2 writer for fracdem meshes.
#pragma once

#include <stdexcept>
#include <string>

#include "fem/mesh.h"

namespace fracdem
{

// Any problem with a mesh file. The message always starts with the file path
// and, when a line is to blame, ":LINE:" (e.g. "body.msh:57: expected 4 node
// tags for element type 4 (tet4), got 3"), so users can jump to the spot.
struct MeshReadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Reads an ASCII Gmsh .msh file, format 2.2 or 4.1 (detected from $MeshFormat).
//
// dim = 3: the body is made of Tet4 (gmsh type 4); dim = 2: Tri3 (2) and
// Quad4 (3) in the x-y plane (z must be 0). dim = 0: the highest element
// dimension present in the file. Elements of lower dimension (points, lines,
// boundary faces) are not part of the body; they only feed node sets.
//
// Result:
//  - nodes: those referenced by body elements, in increasing Gmsh tag order,
//    0-based; X holds their coordinates.
//  - elements in file order; active = 1; region = first physical tag (0 if
//    none). 2D elements are made counter-clockwise; tets are left as they are
//    (an inverted tet is reported by the FE setup).
//  - every physical group (any dimension) -> node_sets[name] (sorted, body
//    nodes only); groups of the body's dimension also -> elem_sets[name].
//    Unnamed groups are called "physical_<tag>"; groups sharing a name are
//    merged. Elements that Gmsh 2.2 repeats once per physical group are
//    merged back into one element.
//
// Throws MeshReadError for: unreadable file or a directory, binary or other
// format versions, unsupported element types of the body's dimension, wrong
// field counts, non-numeric or non-finite fields, physical / entity tags beyond
// int, duplicate node tags, unknown node references, body elements listing a
// node twice, body elements whose size overflows double precision, truncated
// sections or sections shorter than their header count, missing $EndX, empty
// body, elements of a higher dimension than a requested dim, and non-zero z in
// 2D. File text quoted in a message is cut to 60 characters, with control and
// non-ASCII bytes as \xNN. A UTF-8 byte order mark and CRLF line ends are
// accepted.
Mesh read_gmsh(const std::string& path, int dim = 0);

// Writes mesh as a Gmsh 2.2 ASCII file: all nodes, all elements (active or
// not) with physical tag = region, elem_sets as named physical groups (as the
// region tag when a set is exactly one region, otherwise as repeated elements
// with a fresh tag, which read_gmsh merges back), and node_sets not named like
// an elem_set as groups of point elements. Throws std::runtime_error naming
// the path when the file cannot be written.
void write_gmsh22(const Mesh& mesh, const std::string& path);

} // namespace fracdem
