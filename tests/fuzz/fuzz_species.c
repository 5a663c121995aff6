/* Fuzz target for species_parse: any bytes either parse into a species whose generator
 * parameters lsystem_generate accepts or fail with a message; never a crash. A parsed
 * species is not grown here (a valid one may ask for a very large tree). */
#include <stdint.h>
#include <stdlib.h>

#include "species.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    species sp;
    gale_err err = { 0 };
    int rc = species_parse((const char *)data, size, "fuzz.json", &sp, &err);
    if (rc != 0 && err.msg[0] == '\0') {
        abort();
    }
    if (rc == 0 && (sp.name[0] == '\0' || !(sp.E_pa > 0.0) || !(sp.G_pa > 0.0))) {
        abort();
    }
    return 0;
}
