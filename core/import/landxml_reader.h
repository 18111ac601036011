// LandXML 1.2 reader: the first `Surfaces/Surface` of a file, as a LandXmlSurface
// (core/export/landxml_surface.h), streamed with libxml2's xmlTextReader so a large surface is
// never held as a document tree.
//
// Reads what core/export/landxml_writer.h writes, and the TIN of other software's files: points
// with any positive ids, faces in either winding (clockwise faces are turned counter-clockwise),
// `n` and `i` optional. Neighbours are computed from the faces and must agree with `n` where it is
// given. The tinbase extension (docs/cli.md, "LandXML") brings back tags, vertex kinds, features
// and constraint owners; a file without it gives a `free` surface with no features. Other
// software's breaklines and boundaries are not turned into features (LandXML does not tie them to
// the faces). Thread-safety: pure (libxml2 is initialised once per process).
#pragma once

#include <string>

#include "core/base/status.h"
#include "core/export/landxml_surface.h"

namespace tinbase {

// The first surface of the LandXML file at `path`. InvalidArgument whose message starts with
// "<path>, line <n>, <Element>: " for bad input: not XML, not LandXML, no Surface/Definition, a
// non-number or a wrong count of numbers, a duplicate point id, a face naming a point that Pnts
// lacks, a degenerate face, faces that share an edge in one direction, an `n` that disagrees
// with the faces, a tag, feature or ring reference out of range, an invalid ring. IOError when the
// file cannot be opened.
Result<LandXmlSurface> ReadLandXml(const std::string& path);

}  // namespace tinbase
