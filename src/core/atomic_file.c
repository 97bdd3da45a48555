/* Atomic output files: temporary file in the same directory, then rename(2),
 * which replaces the destination in one step on POSIX file systems. */
#include "restir/core/atomic_file.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int ensure_parent_dir(const char *path, rerror *e)
{
    char dir[4096];
    char *slash;
    struct stat st;
    if (strlen(path) >= sizeof dir) return rerror_set(e, "%s: path too long", path);
    strcpy(dir, path);
    slash = strrchr(dir, '/');
    if (!slash || slash == dir) return 0;
    *slash = '\0';
    if (stat(dir, &st) == 0) return S_ISDIR(st.st_mode) ? 0 : rerror_set(e, "%s: not a directory", dir);
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return rerror_set(e, "%s: cannot create directory: %s", dir, strerror(errno));
    return 0;
}

int atomic_file_open(atomic_file *f, const char *path, rerror *e)
{
    memset(f, 0, sizeof *f);
    if (strlen(path) >= sizeof f->path) return rerror_set(e, "%s: path too long", path);
    strcpy(f->path, path);
    snprintf(f->tmp_path, sizeof f->tmp_path, "%s.tmp.%ld", path, (long)getpid());
    if (ensure_parent_dir(path, e)) return -1;
    f->fp = fopen(f->tmp_path, "wb");
    if (!f->fp) return rerror_set(e, "%s: cannot write: %s", path, strerror(errno));
    return 0;
}

int atomic_file_commit(atomic_file *f, rerror *e)
{
    int failed = 0;
    if (!f->fp) return rerror_set(e, "%s: not open", f->path);
    if (fflush(f->fp) != 0 || ferror(f->fp)) failed = 1;
    if (fclose(f->fp) != 0) failed = 1;
    f->fp = NULL;
    if (failed) {
        remove(f->tmp_path);
        return rerror_set(e, "%s: write failed: %s", f->path, strerror(errno));
    }
    if (rename(f->tmp_path, f->path) != 0) {
        int err = errno;
        remove(f->tmp_path);
        return rerror_set(e, "%s: cannot rename into place: %s", f->path, strerror(err));
    }
    return 0;
}

void atomic_file_abort(atomic_file *f)
{
    if (f->fp) {
        fclose(f->fp);
        f->fp = NULL;
    }
    if (f->tmp_path[0]) remove(f->tmp_path);
}
