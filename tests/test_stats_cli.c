/* `restir stats mean-ci`: the one mean and t interval of the results scripts, checked against
 * known values and against the library's stats_mean_ci it is built on. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/metrics/stats.h"
#include "test.h"

static char out[4096];

/* Runs `restir stats mean-ci FILE ARGS` where FILE holds `numbers` (test_cli gives the
 * command /dev/null as stdin). */
static int mean_ci_cli(const char *numbers, const char *args)
{
    const char *in = test_write_file("mean_ci.txt", numbers);
    char path[1024];
    snprintf(path, sizeof path, "%s", in);
    return test_cli(out, sizeof out, "stats mean-ci %s %s", path, args);
}

TEST(stats_cli_mean_ci_exact)
{
    /* 1, 2, 3, 4: mean 2.5, s^2 = 5/3, se = sqrt(5/12); t_{0.975, 3} = 3.182446305284263. */
    double m = 0, h = 0, lo, hi;
    const double x[4] = {1, 2, 3, 4};
    double mean, var;
    CHECK(mean_ci_cli("1\n2\n3\n4\n", "--format '%.15g %.15g'") == 0);
    CHECKF(sscanf(out, "%lf %lf", &m, &h) == 2, "output: %s", out);
    CHECK_NEAR(m, 2.5, 1e-15);
    CHECK_NEAR(h, 3.182446305284263 * sqrt(5.0 / 12.0), 1e-12);
    /* the same as the library's interval */
    stats_mean_var(x, 4, &mean, &var);
    stats_mean_ci(stats_estimate_from_samples(mean, var, 4), 0.95, &lo, &hi);
    CHECK_NEAR(h, 0.5 * (hi - lo), 1e-13);
    /* another level, several numbers per line: t_{0.995, 2} = 9.924843200918276, se = 1/sqrt(3) */
    CHECK(mean_ci_cli("1 2\n 3\n", "--level 0.99 --format '%.15g %.15g'") == 0);
    CHECKF(sscanf(out, "%lf %lf", &m, &h) == 2, "output: %s", out);
    CHECK_NEAR(m, 2.0, 1e-15);
    CHECK_NEAR(h, 9.924843200918276 / sqrt(3.0), 1e-11);
    /* the default format is the scripts' "mean ± half" */
    CHECK(mean_ci_cli("1\n2\n3\n4\n", "") == 0);
    CHECKF(!strcmp(out, "2.5 ± 2.1\n"), "output: '%s'", out);
    CHECK(mean_ci_cli("1\n2\n3\n4\n", "--format '%.1f ± %.1f'") == 0);
    CHECKF(!strcmp(out, "2.5 ± 2.1\n"), "output: '%s'", out);
}

/* The t table of the awk summaries: the quantiles of stats_t_quantile, df = 1..N. */
TEST(stats_cli_t_table)
{
    double t[4];
    CHECK(test_cli(out, sizeof out, "stats t-table --max-dof 4") == 0);
    CHECKF(sscanf(out, "%lf %lf %lf %lf", &t[0], &t[1], &t[2], &t[3]) == 4, "output: %s", out);
    CHECK_NEAR(t[0], 12.706204736174707, 1e-7);
    CHECK_NEAR(t[2], 3.182446305284263, 1e-8);
    CHECK_NEAR(t[3], stats_t_quantile(0.975, 4.0), 1e-8);
    CHECK(test_cli(out, sizeof out, "stats t-table --max-dof 0") == 2);
    CHECK(test_cli(out, sizeof out, "stats t-table extra") == 2);
}

TEST(stats_cli_mean_ci_refuses)
{
    CHECK(mean_ci_cli("", "") == 2);
    CHECKF(strstr(out, "needs two values") && strstr(out, "none"), "output: %s", out);
    CHECK(mean_ci_cli("\n  \n", "") == 2);
    CHECK(mean_ci_cli("3.5\n", "") == 2);
    CHECKF(strstr(out, "needs two values") && strstr(out, "one"), "output: %s", out);
    CHECK(mean_ci_cli("1\n2\nx\n", "") == 2);
    CHECKF(strstr(out, "mean_ci.txt:3:") && strstr(out, "'x'"), "output: %s", out);
    CHECK(mean_ci_cli("1\ninf\n", "") == 2);
    CHECK(mean_ci_cli("1\n2\n", "--level 1") == 2);
    CHECK(mean_ci_cli("1\n2\n", "--format '%s %d'") == 2);
    CHECK(mean_ci_cli("1\n2\n", "--format '%.3g'") == 2);
    CHECK(mean_ci_cli("1\n2\n", "--format '%.3g %.3g %.3g'") == 2);
    CHECK(mean_ci_cli("1\n2\n", "stray") == 2);
    CHECK(test_cli(out, sizeof out, "stats mean-ci") == 2); /* empty stdin */
    CHECKF(strstr(out, "needs two values") && strstr(out, "stdin"), "output: %s", out);
    CHECK(test_cli(out, sizeof out, "stats mean-ci %s/no-such-file", test_tmpdir()) == 2);
    CHECK(test_cli(out, sizeof out, "stats") == 2);
    CHECK(test_cli(out, sizeof out, "stats --help") == 0);
    CHECK(strstr(out, "mean-ci") != NULL);
}
