/* layout.h - layouts drawn in QGIS: a list item {gpkg: FILE, layer: NAME} under
 * `measures`, `releases`, `terrain: zones` or `vegetation` stands for one item per
 * feature of that GeoPackage layer (docs/gis.md).
 *
 * The items are made as YAML nodes in the project's document before it is read, so
 * every check of a typed item applies to them; an error at one names the file, the
 * layer, the feature id and the attribute.  The feature's attribute columns give its
 * keys (NULL: the key is absent; `capacity_serviceability` the nested key
 * capacity: {serviceability}, and likewise the other documented columns), its
 * geometry the `line` (LineString, or a MultiLineString of one line), the `point`
 * (Point) or `area` (Polygon without holes) of a release, or the `polygon` of a zone
 * or forest (Polygon or MultiPolygon, holes and parts joined for the even-odd rule);
 * Z and M values are ignored.  A layer
 * must be in the project's CRS: rockfall does not reproject. */
#ifndef ROCKFALL_LAYOUT_H
#define ROCKFALL_LAYOUT_H

#include <stddef.h>

#include "input/yamldoc.h"
#include "rockfall/project.h"

/* The most features one item expands into. */
#define RF_LAYOUT_FEATURES_MAX 100000

/* A layer read, and the CRS it is in. */
typedef struct rf_layout_layer {
    char *file, *layer;
    rf_mark at;         /* its {gpkg, layer} item in the project */
    long long srs_id;   /* gpkg_spatial_ref_sys */
    char *srs_name, *organization, *definition;
    long long code;     /* organization_coordsys_id */
} rf_layout_layer;

typedef struct rf_layouts {
    rf_layout_layer *v;
    size_t n;
} rf_layouts;

/* Expands every {gpkg, layer} item of the document's lists in place (paths relative to
 * dir) and records the layers read in *used.  Returns 0, or -1 with err at the item. */
int rf_layout_expand(rf_ydoc *d, const char *dir, rf_layouts *used, rf_error *err);
/* Each layer read must be in the project's CRS (none: an undefined one). */
int rf_layout_check_crs(const rf_ydoc *d, const rf_layouts *used, const rf_crs *crs,
                        rf_error *err);
void rf_layouts_free(rf_layouts *used);

#endif
