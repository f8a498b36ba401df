/*
 * i2c_shim.h: what the shim's three sources share (i2c_shim.c: the descriptors, the
 * framing, open/close/dup/read/write; i2c_shim_ioctl.c: ioctl; i2c_shim_stat.c: stat
 * and access). Everything here is hidden from the program the shim is loaded into.
 */
#ifndef FIRMWARE_SIM_I2C_SHIM_H
#define FIRMWARE_SIM_I2C_SHIM_H

#define _GNU_SOURCE
#include <errno.h>
#include <stdint.h>
#include <sys/types.h>

#define SOCKET_ENV "FIRMWARE_SIM_I2C_SOCKET"
#define MAX_FDS 4096
#define MAX_FRAME (1u << 20)
#define HIDDEN __attribute__((visibility("hidden")))

/* libc's own functions, found with dlsym(RTLD_NEXT). */
HIDDEN extern int (*real_close)(int);
HIDDEN void shim_resolve(void);
/* Whether fd is an emulated node, and the bus it opened. */
HIDDEN int shim_is_emulated(int fd);
HIDDEN uint32_t shim_fd_bus(int fd);
/* The bus number of a path this shim answers ("/dev/i2c-<N>" with the socket named),
 * else -1. */
HIDDEN long shim_ours(const char *path);
/* A new connection to the emulator, or -1. */
HIDDEN int shim_connect(int cloexec);
/* One request frame out, its reply frame back (malloc'd), or NULL. Callers of the
 * emulated descriptors hold shim_lock. */
HIDDEN uint8_t *shim_exchange(int fd, const uint8_t *req, uint32_t len, uint32_t *reply_len);
HIDDEN void shim_lock(void);
HIDDEN void shim_unlock(void);
HIDDEN int32_t get_i32(const uint8_t *p);
HIDDEN void put_u16(uint8_t *p, uint16_t v);
HIDDEN void put_u32(uint8_t *p, uint32_t v);
/* A result word to a return value: >= 0 passes, -errno sets errno and gives -1. */
HIDDEN long shim_result(int32_t res);

#endif
