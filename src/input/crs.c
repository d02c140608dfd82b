/* crs.c - coordinate reference systems through PROJ's C API (input/crs.h).
 *
 * Each call works in a PROJ context of its own (created and destroyed here), so that
 * nothing is shared between threads, and PROJ's log goes to the caller's message
 * instead of stderr. */
#include "input/crs.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <proj.h>

/* The last message PROJ logged in this context. */
typedef struct proj_log {
    char text[512];
} proj_log;

static void keep_message(void *data, int level, const char *msg)
{
    proj_log *log = data;
    (void)level;
    if (msg)
        snprintf(log->text, sizeof log->text, "%s", msg);
}

static PJ_CONTEXT *context(proj_log *log)
{
    PJ_CONTEXT *ctx = proj_context_create();
    if (ctx) {
        log->text[0] = '\0';
        proj_log_func(ctx, log, keep_message);
        proj_log_level(ctx, PJ_LOG_ERROR);
    }
    return ctx;
}

static char *copy(const char *s)
{
    return s ? strdup(s) : NULL;
}

/* The authority and code of the CRS: its own identifier, else the one PROJ identifies
 * with full confidence (a .prj in the ESRI flavour names none). */
static void identify(PJ_CONTEXT *ctx, PJ *crs, rf_crs *c)
{
    const char *auth = proj_get_id_auth_name(crs, 0), *code = proj_get_id_code(crs, 0);
    if (auth && code) {
        c->auth = copy(auth);
        c->code = strtol(code, NULL, 10);
        return;
    }
    int *confidence = NULL;
    PJ_OBJ_LIST *found = proj_identify(ctx, crs, "EPSG", NULL, &confidence);
    if (found && proj_list_get_count(found) > 0 && confidence && confidence[0] == 100) {
        PJ *best = proj_list_get(ctx, found, 0);
        const char *a = best ? proj_get_id_auth_name(best, 0) : NULL;
        const char *k = best ? proj_get_id_code(best, 0) : NULL;
        if (a && k) {
            c->auth = copy(a);
            c->code = strtol(k, NULL, 10);
        }
        proj_destroy(best);
    }
    proj_int_list_destroy(confidence);
    proj_list_destroy(found);
}

int rf_crs_resolve(const char *definition, const char *source, rf_crs *c, char *why,
                   size_t cap)
{
    memset(c, 0, sizeof *c);
    proj_log log;
    PJ_CONTEXT *ctx = context(&log);
    if (!ctx) {
        snprintf(why, cap, "out of memory starting PROJ");
        return -1;
    }
    PJ *crs = proj_create(ctx, definition);
    int status = -1;
    if (!crs) {
        int e = proj_context_errno(ctx);
        snprintf(why, cap, "%s", log.text[0] ? log.text
                                 : e ? proj_context_errno_string(ctx, e)
                                     : "not a CRS PROJ knows");
    } else if (!proj_is_crs(crs)) {
        snprintf(why, cap, "PROJ reads it as a coordinate operation, not a CRS");
    } else {
        const char *wkt = proj_as_wkt(ctx, crs, PJ_WKT1_GDAL, NULL);
        c->source = copy(source);
        c->name = copy(proj_get_name(crs));
        c->wkt = copy(wkt);
        identify(ctx, crs, c);
        if (!wkt)
            snprintf(why, cap, "PROJ cannot write it as WKT 1 (%s)",
                     log.text[0] ? log.text : "a CRS WKT 1 cannot express");
        else if (!c->source || !c->name || !c->wkt)
            snprintf(why, cap, "out of memory");
        else
            status = 0;
    }
    proj_destroy(crs);
    proj_context_destroy(ctx);
    if (status)
        rf_crs_free(c);
    return status;
}

char *rf_crs_esri_wkt(const char *wkt, char *why, size_t cap)
{
    proj_log log;
    PJ_CONTEXT *ctx = context(&log);
    if (!ctx) {
        snprintf(why, cap, "out of memory starting PROJ");
        return NULL;
    }
    PJ *crs = proj_create(ctx, wkt);
    const char *esri = crs ? proj_as_wkt(ctx, crs, PJ_WKT1_ESRI, NULL) : NULL;
    char *out = copy(esri);
    if (!out)
        snprintf(why, cap, "%s", log.text[0] ? log.text : "PROJ cannot write it as ESRI WKT");
    proj_destroy(crs);
    proj_context_destroy(ctx);
    return out;
}

void rf_crs_free(rf_crs *c)
{
    free(c->source);
    free(c->name);
    free(c->wkt);
    free(c->auth);
    memset(c, 0, sizeof *c);
}
