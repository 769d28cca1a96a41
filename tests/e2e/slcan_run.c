/*
 * slcan_run - runs a command against an slcan CAN interface that exists only
 * while it runs: a pseudo-terminal switched to the slcan line discipline, as
 * slcand does with a USB-serial adapter (see tests/hal/test_guard.c). To the
 * real-bus guard it is a real CAN bus; nothing is on its other end.
 *
 *   slcan_run COMMAND [ARG...]     every ARG "{}" is replaced by the
 *                                  interface's name (slcan0, ...)
 *
 * Exit status: COMMAND's (128 + N if a signal N ended it); 77 when this
 * kernel has no pseudo-terminals or no slcan; 125 on other set-up errors.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <net/if.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <linux/tty.h>

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: slcan_run COMMAND [ARG...]  ({} is the interface)\n");
        return 125;
    }
    const int master = posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
    if ((master < 0) || (grantpt(master) != 0) || (unlockpt(master) != 0)) {
        fprintf(stderr, "slcan_run: no pseudo-terminals: %s\n", strerror(errno));
        return 77;
    }
    const int tty = ioctl(master, TIOCGPTPEER, O_RDWR | O_NOCTTY | O_CLOEXEC);
    const int disc = N_SLCAN;
    char name[IFNAMSIZ + 1];
    memset(name, 0, sizeof name);
    if ((tty < 0) || (ioctl(tty, TIOCSETD, &disc) != 0) || (ioctl(tty, SIOCGIFNAME, name) != 0)) {
        fprintf(stderr, "slcan_run: no slcan line discipline: %s\n", strerror(errno));
        return 77;
    }
    char **args = calloc((size_t)argc, sizeof *args);
    if (args == NULL) {
        return 125;
    }
    for (int i = 1; i < argc; i++) {
        args[i - 1] = (strcmp(argv[i], "{}") == 0) ? name : argv[i];
    }
    fflush(stdout);
    const pid_t pid = fork();
    if (pid < 0) {
        return 125;
    }
    if (pid == 0) {
        execvp(args[0], args);
        fprintf(stderr, "slcan_run: cannot run %s: %s\n", args[0], strerror(errno));
        _exit(127);
    }
    int st = 0;
    while (waitpid(pid, &st, 0) < 0) {
        if (errno != EINTR) {
            return 125;
        }
    }
    (void)close(tty); /* the interface goes with the line discipline */
    (void)close(master);
    free(args);
    return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}
