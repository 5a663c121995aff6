/* Captions per wind class (caption.h), from the language table. */
#include "caption.h"

#include "lang.h"
#include "wind_scale.h"

const char *caption_for(int lang, int ss_class, int beaufort)
{
    if (ss_class >= WIND_SCALE_CAT1 && ss_class <= WIND_SCALE_CAT5) {
        return lang_text(lang, L_CAPTION_CAT_1 + (ss_class - WIND_SCALE_CAT1));
    }
    int b = beaufort < 0 ? 0 : beaufort > 12 ? 12 : beaufort;
    return lang_text(lang, L_CAPTION_BFT_0 + b);
}
