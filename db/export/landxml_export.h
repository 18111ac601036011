// LandXML export from a store: a surface with its features, constraint owners and the store's CRS
// as a LandXmlSurface (core/export/landxml_surface.h), and the file written through OutputFile
// so that no partial file is ever left behind. Thread-safety: through one Store.
#pragma once

#include <optional>
#include <string>

#include "core/base/status.h"
#include "core/export/landxml_surface.h"
#include "core/geometry/crs.h"
#include "db/query/surface_selection.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

// The whole of `surface`, read in one snapshot: vertices and triangles in id order, the features
// in id order, every constraint row with its owner. Errors: those of SurfaceStore::Load and
// LoadFeatures.
Result<LandXmlSurface> LoadLandXmlSurface(Store& store, const SurfaceInfo& surface);

// A part of a surface (a selection: no features, constraints kept without owners).
LandXmlSurface LandXmlFromLoaded(const SurfaceInfo& surface, const LoadedSurface& loaded,
                                 const std::optional<Crs>& crs);

// What `export --format landxml` writes for a selection: the whole surface
// (LoadLandXmlSurface) when `filter` selects nothing in particular, else LandXmlFromLoaded of
// SelectSurface's part. Errors: theirs.
Result<LandXmlSurface> LoadLandXmlSelection(Store& store, const SurfaceInfo& surface,
                                            const SurfaceFilter& filter);

// Writes `surface` as LandXML to `path` (a temporary file renamed onto it when complete).
// IOError naming the path when it cannot be written.
Status ExportLandXml(const LandXmlSurface& surface, const std::string& path);

}  // namespace tinbase
