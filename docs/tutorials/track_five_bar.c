// Track the five-bar's output point along a crank trajectory, as a control loop would: each
// solve starts from the previous solution (guess aliases passive). C99, no allocation.
#include <math.h>
#include <stdio.h>

#include "five_bar.h"

int main(void) {
    five_bar_params params = FIVE_BAR_PARAMS_DEFAULT;
    double actuated[FIVE_BAR_NUM_ACTUATED];
    double passive[FIVE_BAR_NUM_PASSIVE] = {0.0, 0.33};  // x, y: the home configuration
    double pose[16], residual, conditioning, first_step;
    int orientation, iterations, status;
    five_bar_newton_job job = {
        .n = 1,
        .actuated = actuated,
        .guess = passive,  // tracking: start from the last solution
        .params = (const double*)&params,
        .max_iterations = 30,
        .tolerance = 1e-12,
        .max_step = 0.5,
        .singular_ratio = 1e-10,
        .passive = passive,
        .pose = pose,
        .residual = &residual,
        .conditioning = &conditioning,
        .orientation = &orientation,
        .first_step = &first_step,
        .iterations = &iterations,
        .status = &status,
    };
    for (int tick = 0; tick <= 1000; ++tick) {
        double phase = 6.283185307179586 * tick / 1000.0;
        actuated[0] = 1.86531065 + 0.2 * sin(phase);  // theta1, theta2 (rad) around the home
        actuated[1] = 1.27628200 - 0.1 * sin(phase);
        five_bar_forward_pose(&job);
        if (status != FIVE_BAR_OK) {
            printf("tick %d: Newton status %d\n", tick, status);
            return 1;
        }
        if (tick % 250 == 0)
            printf("tick %4d: x = %+.6f, y = %+.6f (%d iterations, residual %.1e, conditioning %.3f)\n", tick,
                   passive[0], passive[1], iterations, residual, conditioning);
    }
    return 0;
}
