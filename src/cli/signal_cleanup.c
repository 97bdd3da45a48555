/* Removing a command's partial outputs on SIGINT / SIGTERM (signal_cleanup.h). */
#include "signal_cleanup.h"

#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define CLEANUP_MAX 40
#define CLEANUP_PATH 4300

typedef struct {
    char path[CLEANUP_PATH];
    char temps[3][CLEANUP_PATH]; /* PATH.tmp.PID, PATH.staged.PID, PATH.staged.PID.tmp.PID */
    int existed;
    dev_t dev;
    ino_t ino;
} cleanup_entry;

static cleanup_entry entries[CLEANUP_MAX];
static volatile sig_atomic_t entry_count;
static char message[256];
static size_t message_len;

void cleanup_register(const char *path)
{
    cleanup_entry *c;
    struct stat st;
    long pid = (long)getpid();
    int i;
    if (!path || !path[0] || entry_count >= CLEANUP_MAX || strlen(path) + 64 >= CLEANUP_PATH) return;
    for (i = 0; i < entry_count; ++i)
        if (!strcmp(entries[i].path, path)) return;
    c = &entries[entry_count];
    snprintf(c->path, sizeof c->path, "%s", path);
    snprintf(c->temps[0], sizeof c->temps[0], "%s.tmp.%ld", path, pid);
    snprintf(c->temps[1], sizeof c->temps[1], "%s.staged.%ld", path, pid);
    snprintf(c->temps[2], sizeof c->temps[2], "%s.staged.%ld.tmp.%ld", path, pid, pid);
    c->existed = stat(path, &st) == 0;
    c->dev = c->existed ? st.st_dev : 0;
    c->ino = c->existed ? st.st_ino : 0;
    entry_count = entry_count + 1; /* the entry is complete before the handler can see it */
}

void cleanup_remove_temps(void)
{
    int i, k;
    for (i = 0; i < entry_count; ++i)
        for (k = 0; k < 3; ++k) unlink(entries[i].temps[k]);
}

/* The outputs renamed into place by this call (a new inode, or none before). */
static int remove_written(void)
{
    struct stat st;
    int i, removed = 0;
    for (i = 0; i < entry_count; ++i) {
        const cleanup_entry *c = &entries[i];
        if (stat(c->path, &st) != 0) continue;
        if (c->existed && st.st_dev == c->dev && st.st_ino == c->ino) continue;
        removed += unlink(c->path) == 0;
    }
    return removed;
}

static void on_signal(int sig)
{
    ssize_t ignored;
    cleanup_remove_temps();
    remove_written();
    ignored = write(2, message, message_len);
    ignored = write(2, sig == SIGTERM ? "SIGTERM" : "SIGINT", sig == SIGTERM ? 7 : 6);
    ignored = write(2, ": nothing written (partial and finished outputs of this call removed)\n", 70);
    (void)ignored;
    _exit(128 + sig);
}

void cleanup_install(const char *command)
{
    static int installed;
    struct sigaction sa;
    if (installed) return;
    installed = 1;
    snprintf(message, sizeof message, "restir %s: interrupted by ", command);
    message_len = strlen(message);
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaddset(&sa.sa_mask, SIGINT); /* one cleanup, not a second one inside the first */
    sigaddset(&sa.sa_mask, SIGTERM);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}
