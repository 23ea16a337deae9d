/* Host platform of the vector runner (smd_vec.h): stdio files; reads go
 * through POSIX read() so that a FIFO delivers each sample as it comes
 * (fread would wait for a full buffer). */
#define _POSIX_C_SOURCE 200112L
#include <stdio.h>
#include <unistd.h>

#include "smd_vec.h"

#define SMD_MAX_FILES 4
static FILE *g_files[SMD_MAX_FILES];

int smd_io_open(const char *path, int write)
{
    int h;
    for (h = 0; h < SMD_MAX_FILES; h++) {
        if (g_files[h] == 0) {
            g_files[h] = fopen(path, write ? "wb" : "rb");
            return g_files[h] ? h : -1;
        }
    }
    return -1;
}

int smd_io_read(int h, void *buf, int n)
{
    long m = (long)read(fileno(g_files[h]), buf, (size_t)n);
    return m < 0 ? 0 : (int)m;
}

int smd_io_write(int h, const void *buf, int n)
{
    int m = (int)fwrite(buf, 1, (size_t)n, g_files[h]);
    fflush(g_files[h]);
    return m;
}

void smd_io_close(int h)
{
    fclose(g_files[h]);
    g_files[h] = 0;
}

void smd_io_log(const char *msg) { fprintf(stderr, "%s\n", msg); }

int main(int argc, char **argv) { return smd_vec_main(argc, argv); }
