/* mkauthume.c - the releases, rocks and observed stops of the Authume projects
 * (projects/authume, docs/validation.md) from the field data.
 *
 * usage: mkauthume PROFILE [--data DIR] [--project FILE] [--count N] [--stops FILE]
 *   PROFILE    P1 or P2
 *   --data     the field data (../shared/validation/authume)
 *   --project  a project whose terrain is the quarry's (projects/authume/authume-p1.yaml)
 *   --count    trajectories per boulder (20)
 *   --stops    also write the measured stops there, x y z in project coordinates
 *
 * Prints the `rocks:` and `releases:` sections: one rock per measured boulder with its
 * mass (the project's default density: none was measured), one release per boulder
 * from the 4-corner drop zone as an `area`, `count` trajectories each, so every boulder
 * has the same share.  The rocks were dropped from the shovel: its corners' mean
 * height is the centre's height at release, so each release's `height` (of the rock's
 * lowest point above the ground) is that height less the mean ground height over the
 * zone and the boulder's radius. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfall/body.h"
#include "rockfall/project.h"
#include "fixtures/field.h"

/* The mean ground height over the release zone's rectangle (a 40 x 40 grid). */
static double mean_ground(const rf_terrain *t, const rf_field_profile *pr)
{
    double sum = 0.0;
    int n = 0;
    for (int i = 0; i < 40; i++)
        for (int j = 0; j < 40; j++) {
            double x = pr->xlo + (pr->xhi - pr->xlo) * (i + 0.5) / 40.0;
            double y = pr->ylo + (pr->yhi - pr->ylo) * (j + 0.5) / 40.0;
            double z;
            if (rf_terrain_height(t, x, y, &z) >= 0)
                sum += z, n++;
        }
    return n ? sum / n : NAN;
}

int main(int argc, char **argv)
{
    const char *profile = NULL, *data = "../shared/validation/authume";
    const char *project = "projects/authume/authume-p1.yaml", *stops = NULL;
    long count = 20;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--data") && i + 1 < argc)
            data = argv[++i];
        else if (!strcmp(argv[i], "--project") && i + 1 < argc)
            project = argv[++i];
        else if (!strcmp(argv[i], "--stops") && i + 1 < argc)
            stops = argv[++i];
        else if (!strcmp(argv[i], "--count") && i + 1 < argc)
            count = atol(argv[++i]);
        else if (!profile && argv[i][0] != '-')
            profile = argv[i];
        else {
            fprintf(stderr, "usage: mkauthume P1|P2 [--data DIR] [--project FILE] [--count N] "
                            "[--stops FILE]\n");
            return 2;
        }
    }
    if (!profile || count < 1) {
        fprintf(stderr, "mkauthume: a profile (P1 or P2) and a count >= 1 are required\n");
        return 2;
    }
    rf_error err;
    rf_field_profile pr;
    rf_project p;
    if (rf_field_profile_load(data, profile, &pr, &err)) {
        rf_error_print(&err, stderr);
        return 2;
    }
    if (rf_project_load(project, &p, &err)) {
        rf_error_print(&err, stderr);
        rf_field_profile_free(&pr);
        return 2;
    }
    double ground = mean_ground(&p.terrain, &pr), density = RF_FIELD_DENSITY;
    printf("# %zu boulders measured on %s (EXP_endpoints/Endpoints_%s.txt), one rock each;\n"
           "# the release zone: Drop_conditions/positions_%s.xyz, the shovel's mean height\n"
           "# %.3f m, the ground under it %.3f m on average.  Written by tools/mkauthume.c.\n",
           pr.stops.n, profile, profile, profile, pr.height, ground);
    printf("rocks:\n");
    for (size_t k = 0; k < pr.stops.n; k++)
        printf("  - {name: %s-b%02zu, mass: %.3f}\n", profile, k + 1, pr.stops.v[7 * k + 3]);
    printf("releases:\n");
    for (size_t k = 0; k < pr.stops.n; k++) {
        double m = pr.stops.v[7 * k + 3];
        double r = cbrt(3.0 * m / (4.0 * M_PI * density));
        printf("  - {name: %s-%02zu, rock: %s-b%02zu, count: %ld, height: %.3f,\n"
               "     area: [", profile, k + 1, profile, k + 1, count, pr.height - ground - r);
        for (size_t c = 0; c < pr.drop.n; c++)
            printf("%s[%.4f, %.4f]", c ? ", " : "", pr.drop.v[3 * c], pr.drop.v[3 * c + 2]);
        printf("]}\n");
    }
    int rc = 0;
    if (stops) {
        FILE *f = fopen(stops, "w");
        if (!f) {
            perror(stops);
            rc = 2;
        } else {
            fprintf(f, "# The %zu measured stop points of the Authume quarry's profile %s, x y z in\n"
                       "# the project's frame (z up; the file's y is the height).  From\n"
                       "# EXP_endpoints/Endpoints_%s.txt of the field data (Garcia et al. 2022,\n"
                       "# richefeu/AuthumeQuarryRockfalls_Data-in-Brief); tools/mkauthume.c.\n",
                    pr.stops.n, profile, profile);
            for (size_t k = 0; k < pr.stops.n; k++)
                fprintf(f, "%.3f %.3f %.3f\n", pr.stops.v[7 * k], pr.stops.v[7 * k + 2],
                        pr.stops.v[7 * k + 1]);
            rc = fclose(f) ? 2 : 0;
        }
    }
    rf_project_free(&p);
    rf_field_profile_free(&pr);
    return rc;
}
