/* schema_legacy.c - the facts of schema version 1 that lie only in the project text
 * (see schema_legacy.h). */
#include "results/schema_legacy.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "input/yamldoc.h"
#include "results/schema.h"

/* The project text as a document in d; NULL when there is none or it does not load. */
static rf_ydoc *project_doc(const char *yaml, rf_ydoc *d)
{
    if (!yaml || rf_ydoc_load_text(d, "project", yaml, strlen(yaml), NULL))
        return NULL;
    return d;
}

/* The value of a top-level key of the document d, NULL when there is none. */
static rf_ynode *project_get(rf_ydoc *d, const char *key)
{
    rf_ynode *root = rf_ydoc_root(d);
    return root && root->type == YAML_MAPPING_NODE ? rf_ydoc_get(d, root, key) : NULL;
}

static int gives_sel(rf_ydoc *d, const char *name)
{
    int gives = 0;
    rf_ynode *seq = project_get(d, "measures");
    size_t n = seq && seq->type == YAML_SEQUENCE_NODE ? rf_ydoc_seq_size(seq) : 0;
    for (size_t i = 0; i < n; i++) {
        rf_ynode *m = rf_ydoc_seq_item(d, seq, i);
        rf_ynode *mname = m && m->type == YAML_MAPPING_NODE ? rf_ydoc_get(d, m, "name") : NULL;
        if (mname && mname->type == YAML_SCALAR_NODE &&
            !strcmp((const char *)mname->data.scalar.value, name))
            return rf_ydoc_get(d, m, "sel") != NULL;
    }
    return gives;
}

int rf_legacy_fixed_step(const char *project_yaml)
{
    rf_ydoc doc, *d = project_doc(project_yaml, &doc);
    if (!d)
        return 0;
    rf_ynode *sim = project_get(d, "simulation");
    rf_ynode *e = sim && sim->type == YAML_MAPPING_NODE ? rf_ydoc_get(d, sim, "engine") : NULL;
    int fixed = e && e->type == YAML_SCALAR_NODE &&
                !strcmp((const char *)e->data.scalar.value, "fixed_step");
    rf_ydoc_free(d);
    return fixed;
}

int rf_legacy_sel_given(const char *project_yaml, const char *name)
{
    rf_ydoc doc, *d = project_doc(project_yaml, &doc);
    if (!d)
        return -1;
    int gives = gives_sel(d, name ? name : "");
    rf_ydoc_free(d);
    return gives;
}

static char *rules_path(rf_ydoc *d, const char *project_path)
{
    rf_ynode *given = project_get(d, "rules");
    const char *rules = given && given->type == YAML_SCALAR_NODE
                            ? (const char *)given->data.scalar.value
                            : NULL;
    if (!rules)
        return NULL;
    const char *slash = project_path ? strrchr(project_path, '/') : NULL;
    size_t dir = rules[0] == '/' || !slash ? 0 : (size_t)(slash - project_path) + 1;
    size_t n = dir + strlen(rules) + 1;
    char *path = malloc(n);
    if (path)
        snprintf(path, n, "%.*s%s", (int)dir, dir ? project_path : "", rules);
    return path;
}

char *rf_legacy_rules_path(const char *project_yaml, const char *project_path)
{
    rf_ydoc doc, *d = project_doc(project_yaml, &doc);
    if (!d)
        return NULL;
    char *path = rules_path(d, project_path);
    rf_ydoc_free(d);
    return path;
}

/* One run's rules_path and its barriers' sel_source. */
static int fill_run(sqlite3 *db, sqlite3_stmt *set_rules, sqlite3_stmt *barriers,
                    sqlite3_stmt *set_sel, sqlite3_int64 run, const char *yaml,
                    const char *project_path)
{
    rf_ydoc doc, *d = project_doc(yaml, &doc);
    if (!d)
        return SQLITE_OK; /* nothing known: the columns stay NULL */
    char *rules = rules_path(d, project_path);
    int rc = SQLITE_OK;
    if (rules) {
        sqlite3_bind_text(set_rules, 1, rules, -1, SQLITE_TRANSIENT);
        sqlite3_bind_int64(set_rules, 2, run);
        rc = sqlite3_step(set_rules) == SQLITE_DONE ? SQLITE_OK : sqlite3_errcode(db);
        sqlite3_reset(set_rules);
        free(rules);
    }
    sqlite3_bind_int64(barriers, 1, run);
    while (rc == SQLITE_OK && sqlite3_step(barriers) == SQLITE_ROW) {
        const char *name = (const char *)sqlite3_column_text(barriers, 1);
        sqlite3_bind_text(set_sel, 1, gives_sel(d, name ? name : "") ? "given" : "default: MEL/3",
                          -1, SQLITE_STATIC);
        sqlite3_bind_int64(set_sel, 2, sqlite3_column_int64(barriers, 0));
        rc = sqlite3_step(set_sel) == SQLITE_DONE ? SQLITE_OK : sqlite3_errcode(db);
        sqlite3_reset(set_sel);
    }
    sqlite3_reset(barriers);
    rf_ydoc_free(d);
    return rc;
}

int rf_legacy_fill(sqlite3 *db, const char *path, rf_error *err)
{
    sqlite3_stmt *runs = NULL, *set_rules = NULL, *barriers = NULL, *set_sel = NULL;
    int rc = sqlite3_prepare_v2(db, "SELECT id, project_yaml, project_path FROM runs", -1,
                                &runs, NULL);
    if (rc == SQLITE_OK)
        rc = sqlite3_prepare_v2(db, "UPDATE runs SET rules_path = ?1 WHERE id = ?2", -1,
                                &set_rules, NULL);
    if (rc == SQLITE_OK)
        rc = sqlite3_prepare_v2(db,
                                "SELECT id, name FROM measures WHERE run_id = ?1 AND"
                                " kind = 'barrier'",
                                -1, &barriers, NULL);
    if (rc == SQLITE_OK)
        rc = sqlite3_prepare_v2(db, "UPDATE measures SET sel_source = ?1 WHERE id = ?2", -1,
                                &set_sel, NULL);
    while (rc == SQLITE_OK && (rc = sqlite3_step(runs)) == SQLITE_ROW)
        rc = fill_run(db, set_rules, barriers, set_sel, sqlite3_column_int64(runs, 0),
                      (const char *)sqlite3_column_text(runs, 1),
                      (const char *)sqlite3_column_text(runs, 2));
    if (rc == SQLITE_DONE)
        rc = SQLITE_OK;
    sqlite3_finalize(runs);
    sqlite3_finalize(set_rules);
    sqlite3_finalize(barriers);
    sqlite3_finalize(set_sel);
    return rf_sql_status(db, path, rc, "reading the project text of version-1 runs", err);
}
