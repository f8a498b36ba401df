/*
 * i2c_shim_ioctl.c: ioctl on an emulated /dev/i2c-N (see i2c_shim.c). The arguments
 * i2c-dev reads from the caller's memory (struct i2c_rdwr_ioctl_data and its messages,
 * struct i2c_smbus_ioctl_data and its union) are copied into the request, and what the
 * kernel would copy back is copied back; the checks are the emulator's.
 */
#include "i2c_shim.h"

#include <dlfcn.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#define I2C_FUNCS 0x0705
#define I2C_RDWR 0x0707
#define I2C_SMBUS 0x0720
#define I2C_M_RD 0x0001
#define RDWR_MAX_MSGS 42 /* I2C_RDWR_IOCTL_MAX_MSGS */
#define SMBUS_BLOCK 34   /* sizeof(union i2c_smbus_data) */

struct shim_i2c_msg {
    uint16_t addr;
    uint16_t flags;
    uint16_t len;
    uint8_t *buf;
};

struct shim_rdwr {
    struct shim_i2c_msg *msgs;
    uint32_t nmsgs;
};

struct shim_smbus {
    uint8_t read_write;
    uint8_t command;
    uint32_t size;
    uint8_t *data;
};

static int (*real_ioctl)(int, unsigned long, ...);

__attribute__((constructor)) static void resolve_ioctl(void) {
    real_ioctl = dlsym(RTLD_NEXT, "ioctl");
}

static long do_funcs(int fd, unsigned long arg) {
    uint8_t req[1] = {'F'};
    uint32_t n = 0;
    uint8_t *reply = shim_exchange(fd, req, 1, &n);
    if (!reply || n < 12) {
        free(reply);
        return shim_result(-EIO);
    }
    int32_t res = get_i32(reply);
    if (res >= 0) {
        uint64_t funcs = 0;
        for (int i = 0; i < 8; i++) funcs |= (uint64_t)reply[4 + i] << (8 * i);
        *(unsigned long *)arg = (unsigned long)funcs;
    }
    free(reply);
    return shim_result(res);
}

static long do_rdwr(int fd, unsigned long arg) {
    const struct shim_rdwr *rdwr = (const struct shim_rdwr *)arg;
    uint32_t nmsgs = rdwr->nmsgs;
    size_t len = 5;
    if (nmsgs <= RDWR_MAX_MSGS)
        for (uint32_t i = 0; i < nmsgs; i++) len += 6 + rdwr->msgs[i].len;
    uint8_t *req = malloc(len);
    if (!req) return shim_result(-ENOMEM);
    req[0] = 'R';
    put_u32(req + 1, nmsgs);
    size_t at = 5;
    if (nmsgs <= RDWR_MAX_MSGS)
        for (uint32_t i = 0; i < nmsgs; i++) {
            const struct shim_i2c_msg *m = &rdwr->msgs[i];
            put_u16(req + at, m->addr);
            put_u16(req + at + 2, m->flags);
            put_u16(req + at + 4, m->len);
            memcpy(req + at + 6, m->buf, m->len); /* the kernel copies reads in too */
            at += 6 + m->len;
        }
    uint32_t n = 0;
    uint8_t *reply = shim_exchange(fd, req, (uint32_t)len, &n);
    free(req);
    if (!reply) return shim_result(-EIO);
    int32_t res = get_i32(reply);
    if (res >= 0) {
        size_t from = 4;
        for (uint32_t i = 0; i < nmsgs; i++) {
            const struct shim_i2c_msg *m = &rdwr->msgs[i];
            if (!(m->flags & I2C_M_RD)) continue;
            if (from + m->len > n) {
                res = -EIO;
                break;
            }
            memcpy(m->buf, reply + from, m->len);
            from += m->len;
        }
    }
    free(reply);
    return shim_result(res);
}

/* How many bytes of the user's union i2c-dev copies for an SMBus size (i2c-dev.c). */
static size_t smbus_datasize(uint32_t size) {
    switch (size) {
    case 1: /* BYTE */
    case 2: /* BYTE_DATA */
        return 1;
    case 3: /* WORD_DATA */
    case 4: /* PROC_CALL */
        return 2;
    case 5: /* BLOCK_DATA */
    case 6: /* I2C_BLOCK_BROKEN */
    case 7: /* BLOCK_PROC_CALL */
    case 8: /* I2C_BLOCK_DATA */
        return SMBUS_BLOCK;
    default:
        return 0;
    }
}

static long do_smbus(int fd, unsigned long arg) {
    const struct shim_smbus *s = (const struct shim_smbus *)arg;
    size_t size = s->data ? smbus_datasize(s->size) : 0;
    uint8_t req[8 + SMBUS_BLOCK] = {'S', s->read_write, s->command};
    put_u32(req + 3, s->size);
    req[7] = s->data != NULL;
    req[8] = (uint8_t)size;
    if (size) memcpy(req + 9, s->data, size);
    uint32_t n = 0;
    uint8_t *reply = shim_exchange(fd, req, (uint32_t)(9 + size), &n);
    if (!reply || n < 5) {
        free(reply);
        return shim_result(-EIO);
    }
    int32_t res = get_i32(reply);
    size_t back = reply[4];
    if (res >= 0 && back && s->data && back <= size && 5 + back <= n)
        memcpy(s->data, reply + 5, back);
    free(reply);
    return shim_result(res);
}

static long do_plain(int fd, unsigned long cmd, unsigned long arg) {
    uint8_t req[13] = {'I'};
    put_u32(req + 1, (uint32_t)cmd);
    for (int i = 0; i < 8; i++) req[5 + i] = ((uint64_t)arg >> (8 * i)) & 0xff;
    uint32_t n = 0;
    uint8_t *reply = shim_exchange(fd, req, sizeof req, &n);
    int32_t res = reply ? get_i32(reply) : -EIO;
    free(reply);
    return shim_result(res);
}

int ioctl(int fd, unsigned long request, ...) {
    va_list ap;
    va_start(ap, request);
    unsigned long arg = va_arg(ap, unsigned long);
    va_end(ap);
    shim_resolve();
    if (!shim_is_emulated(fd)) return real_ioctl(fd, request, arg);
    long res;
    shim_lock();
    switch (request) {
    case I2C_FUNCS:
        res = do_funcs(fd, arg);
        break;
    case I2C_RDWR:
        res = do_rdwr(fd, arg);
        break;
    case I2C_SMBUS:
        res = do_smbus(fd, arg);
        break;
    default:
        res = do_plain(fd, request, arg);
        break;
    }
    int saved = errno;
    shim_unlock();
    errno = saved;
    return (int)res;
}
