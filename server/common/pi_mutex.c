#include "pi_mutex.h"

int pi_mutex_init(pthread_mutex_t *m)
{
    pthread_mutexattr_t a;
    if (pthread_mutexattr_init(&a)) {
        return pthread_mutex_init(m, NULL);
    }
    int rc = pthread_mutexattr_setprotocol(&a, PTHREAD_PRIO_INHERIT);
    rc = rc ? pthread_mutex_init(m, NULL) : pthread_mutex_init(m, &a);
    pthread_mutexattr_destroy(&a);
    return rc;
}
