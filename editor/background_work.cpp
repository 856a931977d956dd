#include "editor/background_work.h"

#include <pthread.h>
#include <sched.h>

namespace lacet {

void lowerToIdlePriority() {
#ifdef SCHED_IDLE
    sched_param param{};
    param.sched_priority = 0;
    pthread_setschedparam(pthread_self(), SCHED_IDLE, &param);  // refused: it runs as it is
#endif
}

}  // namespace lacet
