/*
 * bench_time - wall time of a command, the median of several runs.
 *
 *   bench_time RUNS COMMAND [ARG...]
 *
 * Runs COMMAND RUNS times one after another, its standard output to
 * /dev/null (standard error kept), and prints on one line the median and
 * each run's time in seconds (CLOCK_MONOTONIC, from fork to exit):
 *   median 0.123456 s runs 0.123456 0.130000 0.120001
 * Exit status: 0; 1 when a run fails (its status is printed); 2 usage.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define MAX_RUNS 101

static double now_s(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ((double)ts.tv_nsec * 1e-9);
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a;
    const double y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    char *end = NULL;
    const long runs = (argc >= 3) ? strtol(argv[1], &end, 10) : 0L;
    if ((argc < 3) || (*end != '\0') || (runs < 1L) || (runs > MAX_RUNS)) {
        fprintf(stderr, "usage: bench_time RUNS(1-%d) COMMAND [ARG...]\n", MAX_RUNS);
        return 2;
    }
    double t[MAX_RUNS];
    for (long i = 0L; i < runs; i++) {
        const double t0 = now_s();
        const pid_t pid = fork();
        if (pid < 0) {
            perror("bench_time: fork");
            return 1;
        }
        if (pid == 0) {
            const int null = open("/dev/null", O_WRONLY);
            if ((null < 0) || (dup2(null, STDOUT_FILENO) < 0)) {
                _exit(126);
            }
            execvp(argv[2], argv + 2);
            fprintf(stderr, "bench_time: cannot run %s: %s\n", argv[2], strerror(errno));
            _exit(127);
        }
        int st = 0;
        while (waitpid(pid, &st, 0) < 0) {
            if (errno != EINTR) {
                perror("bench_time: waitpid");
                return 1;
            }
        }
        t[i] = now_s() - t0;
        if (!WIFEXITED(st) || (WEXITSTATUS(st) != 0)) {
            fprintf(stderr, "bench_time: %s failed (status %d)\n", argv[2],
                    WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st));
            return 1;
        }
    }
    double sorted[MAX_RUNS];
    memcpy(sorted, t, sizeof(double) * (size_t)runs);
    qsort(sorted, (size_t)runs, sizeof(double), cmp_double);
    const double median = ((runs % 2L) == 1L)
                              ? sorted[runs / 2L]
                              : 0.5 * (sorted[(runs / 2L) - 1L] + sorted[runs / 2L]);
    printf("median %.6f s runs", median);
    for (long i = 0L; i < runs; i++) {
        printf(" %.6f", t[i]);
    }
    printf("\n");
    return 0;
}
