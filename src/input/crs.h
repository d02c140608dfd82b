/* crs.h - coordinate reference systems, resolved with PROJ (libproj, its C API).
 *
 * A project's `crs:` is an authority code PROJ knows (`EPSG:2154`, `EPSG:2056`), or the
 * path of a file holding WKT (OGC or ESRI flavour, as a .prj does); without one, a
 * DEM's `.prj` beside it is read.  The results database stores the CRS as OGC WKT 1
 * (the definition a GeoPackage's gpkg_spatial_ref_sys holds), and the raster export
 * writes ESRI WKT 1 beside each grid (the .prj GIS programs read). */
#ifndef ROCKFALL_CRS_H
#define ROCKFALL_CRS_H

#include <stddef.h>

#include "rockfall/project.h"

/* The most bytes of a WKT file read (a CRS's WKT is a few kB). */
#define RF_CRS_FILE_MAX (1u << 20)

/* Resolves `definition` (an authority code, or WKT text) into c: its name, its OGC WKT
 * 1 and its authority and code when PROJ identifies one exactly.  `source` is stored as
 * given.  Returns 0, or -1 with PROJ's reason in why (c then holds nothing). */
int rf_crs_resolve(const char *definition, const char *source, rf_crs *c, char *why,
                   size_t cap);
/* The same WKT in the ESRI flavour, malloc'd; NULL with the reason in why. */
char *rf_crs_esri_wkt(const char *wkt, char *why, size_t cap);
void rf_crs_free(rf_crs *c);

#endif
