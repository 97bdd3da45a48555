/* Private to src/cli. `restir diff-dump A B --stat` when A and B hold K runs each
 * (A/run_00 ... from `restir render --sequence A..B --runs K --dump-dir A`): a paired,
 * per-channel test per frame and stage (diff_dump_runs.c; docs/oracle.md §8). */
#ifndef RESTIR_CLI_DIFF_DUMP_RUNS_H
#define RESTIR_CLI_DIFF_DUMP_RUNS_H

/* 1 if dir holds run_00/manifest.json. */
int diff_dump_has_runs(const char *dir);
/* The paired test; z: the |t| beyond which a row differs (0: the t quantile at K-1 degrees
 * of freedom of a two-sided false alarm of 1e-3 over all rows and channels together,
 * Bonferroni). Exit status:
 * 0 every row passes, 1 one differs, 2 bad input. */
int diff_dump_runs(const char *a, const char *b, double z, int json);

#endif
