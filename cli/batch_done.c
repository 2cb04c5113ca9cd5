/* squama batch's done.json read back: parsed alone, so that the fuzz harness and the
 * manifest tests build it without the rest of the program. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "batch.h"
#include "manifest.h"
#include "squama/params.h"

static const char *json_str(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsString(v) ? v->valuestring : NULL;
}

static double json_num(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

int batch_parse_done(const char *text, size_t len, BatchDone *d)
{
    memset(d, 0, sizeof *d);
    d->r.fitted = -1;
    d->expected = -1;
    cJSON *root = cJSON_ParseWithLength(text, len);
    const char *fmt = json_str(root, "format"), *status = json_str(root, "status");
    const char *id = json_str(root, "id"), *photo = json_str(root, "photo");
    if (!root || !fmt || strcmp(fmt, "squama-batch-row/1") != 0 || !status || !id || !photo ||
        !cli_manifest_id_ok(id)) {
        cJSON_Delete(root);
        return 0;
    }
    snprintf(d->id, sizeof d->id, "%s", id);
    snprintf(d->photo, sizeof d->photo, "%s", photo);
    const char *mask = json_str(root, "mask"), *species = json_str(root, "species");
    const char *expected = json_str(root, "expected");
    const char *pd = json_str(root, "photo_digest"), *md = json_str(root, "mask_digest");
    const char *line_path = json_str(root, "body_line"), *ld = json_str(root, "line_digest");
    const char *settings = json_str(root, "settings");
    snprintf(d->photo_digest, sizeof d->photo_digest, "%s", pd && strlen(pd) == BATCH_DIGEST - 1 ? pd : "");
    snprintf(d->mask_digest, sizeof d->mask_digest, "%s", md && strlen(md) == BATCH_DIGEST - 1 ? md : "");
    snprintf(d->line_digest, sizeof d->line_digest, "%s", ld && strlen(ld) == BATCH_DIGEST - 1 ? ld : "");
    snprintf(d->body_line, sizeof d->body_line, "%s", line_path ? line_path : "");
    d->has_settings = settings != NULL;
    snprintf(d->settings, sizeof d->settings, "%s", settings ? settings : "");
    snprintf(d->mask, sizeof d->mask, "%s", mask ? mask : "");
    snprintf(d->species, sizeof d->species, "%s", species ? species : "");
    d->expected = expected ? cli_manifest_category(expected) : -1;
    double line = json_num(root, "line");
    d->line = isfinite(line) && line >= 0 && line < 1e9 ? (int)line : 0;
    d->r.seconds = json_num(root, "seconds");
    int ok = 1;
    if (strcmp(status, "ok") == 0) {
        const char *cat = json_str(root, "category");
        const cJSON *o = cJSON_GetObjectItemCaseSensitive(root, "objectives");
        d->r.status = BATCH_OK;
        d->r.fitted = cat ? cli_manifest_category(cat) : -1;
        d->r.score = json_num(root, "score");
        d->r.evals = (long)fmax(0, fmin(1e15, json_num(root, "evaluations")));
        const double sw = json_num(root, "strip_body_widths"); /* absent in older rows */
        d->r.strip_widths = isfinite(sw) && sw > 0 && sw < 1e6 ? sw : 0;
        for (int k = 0; k < SQ_OBJ_COUNT; k++)
            d->r.obj[k] = json_num(o, sq_fit_objective_name(k));
        ok = d->r.fitted >= 0 && cJSON_IsObject(o);
    } else if (strcmp(status, "error") == 0) {
        const char *e = json_str(root, "error");
        d->r.status = BATCH_ERROR;
        snprintf(d->r.error, sizeof d->r.error, "%s", e ? e : "failed");
    } else {
        ok = 0;
    }
    d->r.resumed = 1;
    cJSON_Delete(root);
    return ok;
}
