/* Cortex-M4F platform of the vector runner (smd_vec.h): ARM semihosting
 * (QEMU -semihosting-config enable=on,target=native). Files are the host's:
 * the runner reads the vector file and writes its outputs directly, and a
 * FIFO pair carries the processor-in-the-loop samples. */
#include <stdint.h>
#include <string.h>

#include "../smd_vec.h"

enum {
    SYS_OPEN = 0x01,
    SYS_CLOSE = 0x02,
    SYS_WRITE0 = 0x04,
    SYS_WRITE = 0x05,
    SYS_READ = 0x06,
    SYS_GET_CMDLINE = 0x15,
    SYS_EXIT = 0x18
};

static int semihost(int op, void *arg)
{
    register int r0 __asm__("r0") = op;
    register void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

int smd_io_open(const char *path, int write)
{
    uint32_t a[3];
    a[0] = (uint32_t)(uintptr_t)path;
    a[1] = write ? 5u : 1u; /* "wb" : "rb" */
    a[2] = (uint32_t)strlen(path);
    return semihost(SYS_OPEN, a);
}

int smd_io_read(int h, void *buf, int n)
{
    uint32_t a[3];
    a[0] = (uint32_t)h;
    a[1] = (uint32_t)(uintptr_t)buf;
    a[2] = (uint32_t)n;
    return n - semihost(SYS_READ, a); /* SYS_READ returns the bytes not read */
}

int smd_io_write(int h, const void *buf, int n)
{
    uint32_t a[3];
    a[0] = (uint32_t)h;
    a[1] = (uint32_t)(uintptr_t)buf;
    a[2] = (uint32_t)n;
    return n - semihost(SYS_WRITE, a);
}

void smd_io_close(int h)
{
    uint32_t a[1];
    a[0] = (uint32_t)h;
    semihost(SYS_CLOSE, a);
}

void smd_io_log(const char *msg)
{
    semihost(SYS_WRITE0, (void *)msg);
    semihost(SYS_WRITE0, (void *)"\n");
}

void smd_exit(int code)
{
    /* SYS_EXIT with ADP_Stopped_ApplicationExit (0x20026) and, in the
     * parameter block form, the exit code (QEMU accepts both) */
    uint32_t a[2];
    a[0] = 0x20026u;
    a[1] = (uint32_t)code;
    semihost(0x20, a); /* SYS_EXIT_EXTENDED */
    semihost(SYS_EXIT, (void *)(uintptr_t)(code == 0 ? 0x20026u : 0x20024u));
    for (;;) {
    }
}

int main(void)
{
    static char cmd[512];
    static char *argv[8];
    uint32_t a[2];
    int argc = 0;
    char *p;
    a[0] = (uint32_t)(uintptr_t)cmd;
    a[1] = sizeof cmd - 1;
    if (semihost(SYS_GET_CMDLINE, a) != 0) {
        smd_io_log("smd_vec: no command line (-semihosting-config arg=...)");
        return 2;
    }
    cmd[a[1]] = 0;
    for (p = cmd; *p && argc < 8;) {
        while (*p == ' ') *p++ = 0;
        if (!*p) break;
        argv[argc++] = p;
        while (*p && *p != ' ') p++;
    }
    return smd_vec_main(argc, argv);
}
