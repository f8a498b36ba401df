/*
 * i2c_shim.c: /dev/i2c-N nodes for a process tree, answered by firmware_sim's Pi-puck
 * emulator over a Unix socket. Loaded with LD_PRELOAD; written for this project. This
 * file: the descriptors, the framing, open/close/dup/fcntl, read and write (ioctl is in
 * i2c_shim_ioctl.c, stat and access in i2c_shim_stat.c).
 *
 * When FIRMWARE_SIM_I2C_SOCKET names a socket, opening "/dev/i2c-<N>" connects to it
 * and asks the emulator for bus N; the connected socket *is* the file descriptor the
 * caller gets, so select/poll/close see a real descriptor. ioctl, read and write on
 * such a descriptor are sent to the emulator, which plays the kernel's i2c-dev and the
 * bus (every check and error code is the emulator's, in Python). Everything else goes
 * to libc untouched.
 *
 * dup, dup2, dup3 and fcntl's F_DUPFD(_CLOEXEC) carry the mark to the new descriptor
 * (it shares the connection, as a duplicate shares i2c-dev's open file); fopen, whose
 * open is inside libc, is not covered. stat, lstat, fstat, fstatat (and their 64 forms,
 * the symbols of glibc 2.33 and later), access and faccessat see a node the emulator has
 * as a character device (major 89, mode 0660), and no node where it has none.
 *
 * Framing, both ways: a little-endian u32 length, then that many bytes. A request
 * starts with an op byte; a reply starts with an i32 result (>= 0, or -errno).
 *   OPEN   'O' u32 bus, i32 flags            -> i32
 *   IOCTL  'I' u32 cmd, u64 arg              -> i32            (I2C_SLAVE, PEC, ...)
 *   FUNCS  'F'                               -> i32, u64 funcs
 *   RDWR   'R' u32 nmsgs, nmsgs x {u16 addr, u16 flags, u16 len, len bytes}
 *                                            -> i32, then each read message's bytes
 *   SMBUS  'S' u8 read_write, u8 command, u32 size, u8 has_data, u8 n, n bytes
 *                                            -> i32, u8 n, n bytes (copied back)
 *   READ   'r' u32 count                     -> i32, that many bytes
 *   WRITE  'w' bytes                         -> i32
 *   EXISTS 'E' u32 bus (no OPEN needed)      -> i32 (0, -EACCES: there but refused, -ENOENT)
 * A user pointer the caller got wrong crashes here where the kernel would say EFAULT.
 */
#include "i2c_shim.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

int (*real_close)(int);
static int (*real_open)(const char *, int, ...);
static int (*real_open64)(const char *, int, ...);
static int (*real_openat)(int, const char *, int, ...);
static int (*real_openat64)(int, const char *, int, ...);
static int (*real_dup)(int);
static int (*real_dup2)(int, int);
static int (*real_dup3)(int, int, int);
static int (*real_fcntl)(int, int, ...);
static int (*real_fcntl64)(int, int, ...);
static ssize_t (*real_read)(int, void *, size_t);
static ssize_t (*real_write)(int, const void *, size_t);

/* Descriptors that are emulated nodes; each exchange holds the lock (one bus). */
static unsigned char emulated[MAX_FDS];
static uint32_t fd_bus[MAX_FDS]; /* the bus an emulated descriptor opened */
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;

void shim_resolve(void) {
    if (real_close) return;
    real_open = dlsym(RTLD_NEXT, "open");
    real_open64 = dlsym(RTLD_NEXT, "open64");
    real_openat = dlsym(RTLD_NEXT, "openat");
    real_openat64 = dlsym(RTLD_NEXT, "openat64");
    real_read = dlsym(RTLD_NEXT, "read");
    real_write = dlsym(RTLD_NEXT, "write");
    real_dup = dlsym(RTLD_NEXT, "dup");
    real_dup2 = dlsym(RTLD_NEXT, "dup2");
    real_dup3 = dlsym(RTLD_NEXT, "dup3");
    real_fcntl = dlsym(RTLD_NEXT, "fcntl");
    real_fcntl64 = dlsym(RTLD_NEXT, "fcntl64");
    if (!real_fcntl64) real_fcntl64 = real_fcntl;
    real_close = dlsym(RTLD_NEXT, "close");
}

__attribute__((constructor)) static void shim_init(void) { shim_resolve(); }

int shim_is_emulated(int fd) { return fd >= 0 && fd < MAX_FDS && emulated[fd]; }

uint32_t shim_fd_bus(int fd) { return shim_is_emulated(fd) ? fd_bus[fd] : 0; }

void shim_lock(void) { pthread_mutex_lock(&lock); }

void shim_unlock(void) { pthread_mutex_unlock(&lock); }

/* "/dev/i2c-<digits>" -> the bus number, else -1. */
static long bus_of(const char *path) {
    static const char prefix[] = "/dev/i2c-";
    if (!path || strncmp(path, prefix, sizeof prefix - 1) != 0) return -1;
    const char *p = path + sizeof prefix - 1;
    if (*p < '0' || *p > '9') return -1;
    long bus = 0;
    for (; *p; p++) {
        if (*p < '0' || *p > '9' || bus > 1000000) return -1;
        bus = bus * 10 + (*p - '0');
    }
    return bus;
}

static int send_all(int fd, const void *data, size_t len) {
    const char *p = data;
    while (len > 0) {
        ssize_t n = send(fd, p, len, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return -1;
        p += n;
        len -= (size_t)n;
    }
    return 0;
}

static int recv_all(int fd, void *data, size_t len) {
    char *p = data;
    while (len > 0) {
        ssize_t n = recv(fd, p, len, 0);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return -1;
        p += n;
        len -= (size_t)n;
    }
    return 0;
}

/* Send one request frame and receive the reply frame into a malloc'd buffer. */
uint8_t *shim_exchange(int fd, const uint8_t *req, uint32_t len, uint32_t *reply_len) {
    uint8_t head[4] = {len & 0xff, (len >> 8) & 0xff, (len >> 16) & 0xff, len >> 24};
    if (send_all(fd, head, 4) || send_all(fd, req, len)) return NULL;
    if (recv_all(fd, head, 4)) return NULL;
    uint32_t n = head[0] | head[1] << 8 | head[2] << 16 | (uint32_t)head[3] << 24;
    if (n < 4 || n > MAX_FRAME) return NULL;
    uint8_t *reply = malloc(n);
    if (!reply) return NULL;
    if (recv_all(fd, reply, n)) {
        free(reply);
        return NULL;
    }
    *reply_len = n;
    return reply;
}

int32_t get_i32(const uint8_t *p) {
    return (int32_t)(p[0] | p[1] << 8 | p[2] << 16 | (uint32_t)p[3] << 24);
}

void put_u16(uint8_t *p, uint16_t v) { p[0] = v & 0xff; p[1] = v >> 8; }

void put_u32(uint8_t *p, uint32_t v) {
    for (int i = 0; i < 4; i++) p[i] = (v >> (8 * i)) & 0xff;
}

/* A result frame to a return value: >= 0 passes, -errno sets errno and gives -1. */
long shim_result(int32_t res) {
    if (res < 0) {
        errno = -res;
        return -1;
    }
    return res;
}

int shim_connect(int cloexec) {
    const char *path = getenv(SOCKET_ENV);
    struct sockaddr_un addr;
    memset(&addr, 0, sizeof addr);
    addr.sun_family = AF_UNIX;
    if (!path || strlen(path) >= sizeof addr.sun_path) return -1;
    strcpy(addr.sun_path, path);
    int fd = socket(AF_UNIX, SOCK_STREAM | (cloexec ? SOCK_CLOEXEC : 0), 0);
    if (fd < 0) return -1;
    if (fd >= MAX_FDS || connect(fd, (struct sockaddr *)&addr, sizeof addr) < 0) {
        real_close(fd);
        return -1;
    }
    return fd;
}

static int emulated_open(long bus, int flags) {
    int fd = shim_connect(flags & O_CLOEXEC);
    if (fd < 0) {
        errno = ENOENT; /* no emulator: no node */
        return -1;
    }
    uint8_t req[9] = {'O'};
    put_u32(req + 1, (uint32_t)bus);
    put_u32(req + 5, (uint32_t)flags);
    uint32_t n = 0;
    uint8_t *reply = shim_exchange(fd, req, sizeof req, &n);
    int32_t res = reply ? get_i32(reply) : -ENOENT;
    free(reply);
    if (res < 0) {
        real_close(fd);
        errno = -res;
        return -1;
    }
    emulated[fd] = 1;
    fd_bus[fd] = (uint32_t)bus;
    return fd;
}

/* Whether this open is ours: an emulator is named and the path is an i2c node. */
long shim_ours(const char *path) {
    shim_resolve();
    if (!getenv(SOCKET_ENV)) return -1;
    return bus_of(path);
}

#define OPEN_MODE(flags, mode)                                   \
    do {                                                         \
        if ((flags) & (O_CREAT | __O_TMPFILE)) {                 \
            va_list ap;                                          \
            va_start(ap, flags);                                 \
            mode = va_arg(ap, int);                              \
            va_end(ap);                                          \
        }                                                        \
    } while (0)

int open(const char *path, int flags, ...) {
    int mode = 0;
    OPEN_MODE(flags, mode);
    long bus = shim_ours(path);
    if (bus >= 0) return emulated_open(bus, flags);
    return real_open(path, flags, mode);
}

int open64(const char *path, int flags, ...) {
    int mode = 0;
    OPEN_MODE(flags, mode);
    long bus = shim_ours(path);
    if (bus >= 0) return emulated_open(bus, flags);
    return real_open64(path, flags, mode);
}

int openat(int dirfd, const char *path, int flags, ...) {
    int mode = 0;
    OPEN_MODE(flags, mode);
    long bus = shim_ours(path); /* an absolute path ignores dirfd */
    if (bus >= 0) return emulated_open(bus, flags);
    return real_openat(dirfd, path, flags, mode);
}

int openat64(int dirfd, const char *path, int flags, ...) {
    int mode = 0;
    OPEN_MODE(flags, mode);
    long bus = shim_ours(path);
    if (bus >= 0) return emulated_open(bus, flags);
    return real_openat64(dirfd, path, flags, mode);
}

/* _FORTIFY_SOURCE's checked entry points. */
int __open_2(const char *path, int flags) { return open(path, flags); }
int __open64_2(const char *path, int flags) { return open64(path, flags); }
int __openat_2(int dirfd, const char *path, int flags) { return openat(dirfd, path, flags); }
int __openat64_2(int dirfd, const char *path, int flags) {
    return openat64(dirfd, path, flags);
}

int close(int fd) {
    shim_resolve();
    if (shim_is_emulated(fd)) {
        pthread_mutex_lock(&lock);
        emulated[fd] = 0;
        pthread_mutex_unlock(&lock);
    }
    return real_close(fd);
}

/* A duplicate shares the open file (the connection), as it shares i2c-dev's client;
 * a descriptor a dup2 replaces is no longer ours. */
static int mark_dup(int oldfd, int newfd) {
    if (newfd >= 0 && newfd < MAX_FDS) {
        pthread_mutex_lock(&lock);
        int ours_too = shim_is_emulated(oldfd);
        if (ours_too) fd_bus[newfd] = fd_bus[oldfd];
        emulated[newfd] = ours_too;
        pthread_mutex_unlock(&lock);
    }
    return newfd;
}

int dup(int oldfd) {
    shim_resolve();
    return mark_dup(oldfd, real_dup(oldfd));
}

int dup2(int oldfd, int newfd) {
    shim_resolve();
    int res = real_dup2(oldfd, newfd);
    return res < 0 || oldfd == newfd ? res : mark_dup(oldfd, res);
}

int dup3(int oldfd, int newfd, int flags) {
    shim_resolve();
    return mark_dup(oldfd, real_dup3(oldfd, newfd, flags));
}

/* fcntl's third argument is an int or a pointer: passed on as a pointer-sized word. */
#define FCNTL_BODY(real)                                                   \
    va_list ap;                                                            \
    va_start(ap, cmd);                                                     \
    void *arg = va_arg(ap, void *);                                        \
    va_end(ap);                                                            \
    shim_resolve();                                                             \
    int res = real(fd, cmd, arg);                                          \
    if ((cmd == F_DUPFD || cmd == F_DUPFD_CLOEXEC) && res >= 0) mark_dup(fd, res); \
    return res

int fcntl(int fd, int cmd, ...) { FCNTL_BODY(real_fcntl); }
int fcntl64(int fd, int cmd, ...) { FCNTL_BODY(real_fcntl64); }

ssize_t read(int fd, void *buf, size_t count) {
    shim_resolve();
    if (!shim_is_emulated(fd)) return real_read(fd, buf, count);
    if (count > 8192) count = 8192; /* i2cdev_read's cap */
    uint8_t req[5] = {'r'};
    put_u32(req + 1, (uint32_t)count);
    shim_lock();
    uint32_t n = 0;
    uint8_t *reply = shim_exchange(fd, req, sizeof req, &n);
    shim_unlock();
    int32_t res = reply ? get_i32(reply) : -EIO;
    if (res > 0) {
        if ((size_t)res > count || 4 + (size_t)res > n) res = -EIO;
        else memcpy(buf, reply + 4, (size_t)res);
    }
    free(reply);
    return shim_result(res);
}

ssize_t write(int fd, const void *buf, size_t count) {
    shim_resolve();
    if (!shim_is_emulated(fd)) return real_write(fd, buf, count);
    if (count > 8192) count = 8192; /* i2cdev_write's cap */
    uint8_t *req = malloc(1 + count);
    if (!req) return shim_result(-ENOMEM);
    req[0] = 'w';
    memcpy(req + 1, buf, count);
    shim_lock();
    uint32_t n = 0;
    uint8_t *reply = shim_exchange(fd, req, (uint32_t)(1 + count), &n);
    shim_unlock();
    free(req);
    int32_t res = reply ? get_i32(reply) : -EIO;
    free(reply);
    return shim_result(res);
}
