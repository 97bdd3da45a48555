/* The render command's name tables (src/cli/render_args.h). */
#include "render_args.h"

const char *const method_names[] = {"aov", "pt", "restir", NULL};
const char *aov_choices[AOV_CHOICE_COUNT + 1];

void fill_aov_choices(void)
{
    int i;
    for (i = 0; i < AOV_CHOICE_DUPLICATES; ++i) aov_choices[i] = aov_names[i];
    aov_choices[AOV_CHOICE_DUPLICATES] = "duplicates";
    aov_choices[AOV_CHOICE_AGE] = "age";
    aov_choices[AOV_CHOICE_COUNT] = NULL;
}
