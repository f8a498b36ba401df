/*
 * i2c_shim_stat.c: stat, lstat, fstat, fstatat (and the 64 forms of glibc 2.33 and
 * later), access and faccessat for the emulated nodes (see i2c_shim.c): a node the
 * emulator has is i2c-dev's character device (major 89, minor N, mode 0660), a node it
 * has not is ENOENT; access for reading or writing is EACCES when the emulator refuses
 * opens (a user outside the i2c group). Other paths and descriptors go to libc.
 */
#include "i2c_shim.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <time.h>
#include <unistd.h>


static int (*real_stat)(const char *, struct stat *);
static int (*real_stat64)(const char *, struct stat64 *);
static int (*real_lstat)(const char *, struct stat *);
static int (*real_lstat64)(const char *, struct stat64 *);
static int (*real_fstat)(int, struct stat *);
static int (*real_fstat64)(int, struct stat64 *);
static int (*real_fstatat)(int, const char *, struct stat *, int);
static int (*real_fstatat64)(int, const char *, struct stat64 *, int);
static int (*real_access)(const char *, int);
static int (*real_faccessat)(int, const char *, int, int);

__attribute__((constructor)) static void resolve_stat(void) {
    real_stat = dlsym(RTLD_NEXT, "stat");
    real_stat64 = dlsym(RTLD_NEXT, "stat64");
    real_lstat = dlsym(RTLD_NEXT, "lstat");
    real_lstat64 = dlsym(RTLD_NEXT, "lstat64");
    real_fstat = dlsym(RTLD_NEXT, "fstat");
    real_fstat64 = dlsym(RTLD_NEXT, "fstat64");
    real_fstatat = dlsym(RTLD_NEXT, "fstatat");
    real_fstatat64 = dlsym(RTLD_NEXT, "fstatat64");
    real_access = dlsym(RTLD_NEXT, "access");
    real_faccessat = dlsym(RTLD_NEXT, "faccessat");
}

/* Ask the emulator about bus N: 0 (there), -EACCES (there, not ours to open), -ENOENT. */
static int32_t node_state(long bus) {
    int fd = shim_connect(1);
    if (fd < 0) return -ENOENT;
    uint8_t req[5] = {'E'};
    put_u32(req + 1, (uint32_t)bus);
    uint32_t n = 0;
    uint8_t *reply = shim_exchange(fd, req, sizeof req, &n);
    int32_t res = reply ? get_i32(reply) : -ENOENT;
    free(reply);
    real_close(fd);
    return res;
}

#define FILL_NODE(st, bus)                               \
    do {                                                 \
        memset((st), 0, sizeof *(st));                   \
        (st)->st_mode = S_IFCHR | 0660;                  \
        (st)->st_rdev = makedev(89, (unsigned)(bus));    \
        (st)->st_nlink = 1;                              \
        (st)->st_blksize = 4096;                         \
        (st)->st_atime = (st)->st_mtime = (st)->st_ctime = time(NULL); \
    } while (0)

/* A path stat: ours when the emulator is named and the path is a node. */
#define STAT_PATH(st, path, real_call)                   \
    do {                                                 \
        shim_resolve();                                       \
        long bus = shim_ours(path);                           \
        if (bus < 0) return real_call;                   \
        if (node_state(bus) == -ENOENT) {                \
            errno = ENOENT;                              \
            return -1;                                   \
        }                                                \
        FILL_NODE(st, bus);                              \
        return 0;                                        \
    } while (0)

#define STAT_FD(st, fd, real_call)                       \
    do {                                                 \
        if (!shim_is_emulated(fd)) return real_call;          \
        FILL_NODE(st, shim_fd_bus(fd));                       \
        return 0;                                        \
    } while (0)

int stat(const char *path, struct stat *st) { STAT_PATH(st, path, real_stat(path, st)); }
int stat64(const char *path, struct stat64 *st) { STAT_PATH(st, path, real_stat64(path, st)); }
int lstat(const char *path, struct stat *st) { STAT_PATH(st, path, real_lstat(path, st)); }
int lstat64(const char *path, struct stat64 *st) {
    STAT_PATH(st, path, real_lstat64(path, st));
}
int fstat(int fd, struct stat *st) { STAT_FD(st, fd, real_fstat(fd, st)); }
int fstat64(int fd, struct stat64 *st) { STAT_FD(st, fd, real_fstat64(fd, st)); }

int fstatat(int dirfd, const char *path, struct stat *st, int flags) {
    if (!*path && (flags & AT_EMPTY_PATH))
        STAT_FD(st, dirfd, real_fstatat(dirfd, path, st, flags));
    STAT_PATH(st, path, real_fstatat(dirfd, path, st, flags));
}

int fstatat64(int dirfd, const char *path, struct stat64 *st, int flags) {
    if (!*path && (flags & AT_EMPTY_PATH))
        STAT_FD(st, dirfd, real_fstatat64(dirfd, path, st, flags));
    STAT_PATH(st, path, real_fstatat64(dirfd, path, st, flags));
}

/* access: F_OK when the node is there; reading or writing also needs the permission. */
static int node_access(long bus, int mode) {
    int32_t state = node_state(bus);
    if (state == -ENOENT || (state == -EACCES && (mode & (R_OK | W_OK | X_OK)))) {
        errno = -state;
        return -1;
    }
    if (mode & X_OK) {
        errno = EACCES;
        return -1;
    }
    return 0;
}

int access(const char *path, int mode) {
    shim_resolve();
    long bus = shim_ours(path);
    return bus < 0 ? real_access(path, mode) : node_access(bus, mode);
}

int faccessat(int dirfd, const char *path, int mode, int flags) {
    shim_resolve();
    long bus = shim_ours(path);
    return bus < 0 ? real_faccessat(dirfd, path, mode, flags) : node_access(bus, mode);
}
