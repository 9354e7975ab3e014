"""The C texts of the exported files, as data: ``str.format`` templates of pampipe_plan.h, pampipe_plan.c and
the Arduino example sketch, filled by :mod:`.sources`.

Doubled braces are C's braces; ``{name}`` fields are filled in (``!r``: Python's shortest round-trip
repr of a float, which C reads back to the same double).
"""

#: pampipe_plan.h; fields: see :func:`pampipe.export.sources.header`.
HEADER = """{top}
#ifndef PAMPIPE_PLAN_H
#define PAMPIPE_PLAN_H

#ifdef __cplusplus
extern "C" {{
#endif

#define PAMPIPE_MISSION_HASH {hash_mark}  /* this export's hash: pampipe_plan.c refuses another header */
#define PAMPIPE_SEGMENTS {segments}                 /* the mission's segment count */
#ifdef PAMPIPE_REAL_FLOAT
typedef float pampipe_real;
#else
typedef double pampipe_real;               /* float when compiled with -DPAMPIPE_REAL_FLOAT */
#endif

#define PAMPIPE_OK 0
{codes}

#define PAMPIPE_MISSION_PAYLOAD_KG ((pampipe_real){payload!r})
#define PAMPIPE_DIAMETER_MAX_M ((pampipe_real){diameter_max!r})   /* bore: 0 < D <= this */
#define PAMPIPE_INCLINE_MAX_RAD ((pampipe_real){incline_max!r}) /* |incline| <= this (pi/2) */
#define PAMPIPE_FRICTION_MAX ((pampipe_real){friction_max!r})      /* 0 <= friction <= this */
#define PAMPIPE_FRICTION_MIN ((pampipe_real){friction_min!r})     /* below it: PAMPIPE_NO_FRICTION */
#define PAMPIPE_PAYLOAD_MAX_KG ((pampipe_real){payload_max!r})  /* 0 <= payload <= this */
#define PAMPIPE_SUPPLY_PRESSURE_PA ((pampipe_real){supply!r})

{function_doc}
int pampipe_required_pressure(pampipe_real inner_diameter_m, pampipe_real incline_rad, pampipe_real friction,
                              pampipe_real payload_kg, pampipe_real pressure_Pa[PAMPIPE_SEGMENTS]);

#define PAMPIPE_SECTIONS {sections}
#define PAMPIPE_GAIT_STEPS 7
#define PAMPIPE_VALVE_CLOSED 0
#define PAMPIPE_VALVE_FILL 1
#define PAMPIPE_VALVE_VENT (-1)

typedef struct {{
    signed char valve[PAMPIPE_SEGMENTS];        /* during the transition into this step */
    unsigned char anchored[PAMPIPE_SEGMENTS];   /* 1 where the segment holds the wall in this step */
    pampipe_real duration_s;                    /* of the transition into this step [s] */
    pampipe_real pressure_Pa[PAMPIPE_SEGMENTS]; /* gauge pressures at the end of the step [Pa] */
}} pampipe_gait_step;

typedef struct {{
    const char *name;
    pampipe_real inner_diameter_m;              /* [m] */
    pampipe_real incline_rad;                   /* [rad] */
    pampipe_real friction;                      /* [-] */
    pampipe_real length_m;                      /* [m] */
    int reason;                                 /* PAMPIPE_OK if the robot can cross it */
    pampipe_real cycle_time_s;                  /* [s] */
    pampipe_real stride_m;                      /* advance per cycle [m] */
    pampipe_gait_step step[PAMPIPE_GAIT_STEPS]; /* I..VII */
}} pampipe_gait_section;

{table_doc}
extern const pampipe_gait_section pampipe_gait[PAMPIPE_SECTIONS];
extern const char *const pampipe_segment_name[PAMPIPE_SEGMENTS];
extern const char *const pampipe_step_name[PAMPIPE_GAIT_STEPS];

#ifdef __cplusplus
}}
#endif

#endif /* PAMPIPE_PLAN_H */
"""

#: pampipe_plan.c; fields: see :func:`pampipe.export.sources.source`.
SOURCE = """{top}
#include <math.h>

#include "pampipe_plan.h"

#if !defined(PAMPIPE_MISSION_HASH) || PAMPIPE_MISSION_HASH != {hash_mark}
#error "pampipe_plan.h comes from another export than pampipe_plan.c: export the mission again"
#endif

{prelude}
{names_comment}const char *const pampipe_segment_name[PAMPIPE_SEGMENTS] = {names};
const char *const pampipe_step_name[PAMPIPE_GAIT_STEPS] = {steps};

int pampipe_required_pressure(pampipe_real inner_diameter_m, pampipe_real incline_rad, pampipe_real friction,
                              pampipe_real payload_kg, pampipe_real pressure_Pa[PAMPIPE_SEGMENTS])
{{
{declarations}    int i, reason = PAMPIPE_OK;

    for (i = 0; i < PAMPIPE_SEGMENTS; ++i) {{
        pressure_Pa[i] = PAMPIPE_NAN;
    }}
    /* every comparison is false for NaN, so NaN fails each range; so do +-inf */
    if (!(inner_diameter_m > PAMPIPE_R(0.0) && inner_diameter_m <= PAMPIPE_DIAMETER_MAX_M)
        || !(incline_rad >= -PAMPIPE_INCLINE_MAX_RAD && incline_rad <= PAMPIPE_INCLINE_MAX_RAD)
        || !(friction >= PAMPIPE_R(0.0) && friction <= PAMPIPE_FRICTION_MAX)
        || !(payload_kg >= PAMPIPE_R(0.0) && payload_kg <= PAMPIPE_PAYLOAD_MAX_KG)) {{
        return PAMPIPE_BAD_ARGUMENT;
    }}
    if (!(friction >= PAMPIPE_FRICTION_MIN)) {{
        return PAMPIPE_NO_FRICTION;
    }}
    if (inner_diameter_m <= {narrowest}) {{ /* rest diameters: {rest} */
        return PAMPIPE_NARROW;
    }}
    if (inner_diameter_m >= {widest}) {{ /* braid limits D(B/sqrt 3): {largest} */
        return PAMPIPE_WIDE;
    }}
    /* {operations} operations generated from pampipe.model.muscle.Muscle.closed_form_pressure */
{statements}
    for (i = 0; i < PAMPIPE_SEGMENTS; ++i) {{
#ifdef PAMPIPE_REAL_FLOAT
        /* float rounds P = P_a + x with cancellation, up to 2e-6 of P below the double answer: round
           up by 5e-6 of P, so that the float law never asks for less than holds */
        pressure_Pa[i] += PAMPIPE_R(5e-6) * PAMPIPE_FABS(pressure_Pa[i]);
#endif
        if (!(pressure_Pa[i] <= {pressure_limit})) {{ /* {pressure_limit_words}; NaN, inf too */
            reason = PAMPIPE_ABOVE_SUPPLY;
        }}
    }}
    return reason;
}}

const pampipe_gait_section pampipe_gait[PAMPIPE_SECTIONS] = {{
{table}
}};
"""

#: The Arduino example sketch; fields: see :func:`pampipe.export.sources.sketch`.
SKETCH = """{top}
#include "pampipe_plan.h"

#if !defined(PAMPIPE_MISSION_HASH) || PAMPIPE_MISSION_HASH != {hash_mark}
#error "pampipe_plan.h comes from another export than this sketch: export the mission again"
#endif

static const uint8_t FILL_PIN[PAMPIPE_SEGMENTS] = {{22, 24, 26}};
static const uint8_t VENT_PIN[PAMPIPE_SEGMENTS] = {{23, 25, 27}};
static const uint8_t SENSOR_PIN[PAMPIPE_SEGMENTS] = {{A0, A1, A2}};

static pampipe_real gauge_pressure_Pa(uint8_t segment)
{{
    pampipe_real volts = analogRead(SENSOR_PIN[segment]) * (pampipe_real)(5.0 / 1023.0);
    return (volts - (pampipe_real)0.5) * (pampipe_real)(1.0e6 / 4.0);
}}

static void set_valve(uint8_t segment, int action)
{{
    digitalWrite(FILL_PIN[segment], action == PAMPIPE_VALVE_FILL ? HIGH : LOW);
    digitalWrite(VENT_PIN[segment], action == PAMPIPE_VALVE_VENT ? HIGH : LOW);
}}

static void walk_step(const pampipe_gait_step *step)
{{
    unsigned long start = millis();
    unsigned long limit = (unsigned long)(1500 * step->duration_s);
    bool opened[PAMPIPE_SEGMENTS];
    bool busy = true;
    for (uint8_t i = 0; i < PAMPIPE_SEGMENTS; ++i) {{
        opened[i] = step->valve[i] != PAMPIPE_VALVE_CLOSED;
        set_valve(i, step->valve[i]);
    }}
    while (busy && millis() - start < limit) {{
        busy = false;
        for (uint8_t i = 0; i < PAMPIPE_SEGMENTS; ++i) {{
            pampipe_real p = gauge_pressure_Pa(i);
            if ((step->valve[i] == PAMPIPE_VALVE_FILL && p >= step->pressure_Pa[i])
                || (step->valve[i] == PAMPIPE_VALVE_VENT && p <= step->pressure_Pa[i])) {{
                opened[i] = false;
                set_valve(i, PAMPIPE_VALVE_CLOSED);
            }}
            busy = busy || opened[i];
        }}
    }}
    for (uint8_t i = 0; i < PAMPIPE_SEGMENTS; ++i) {{
        set_valve(i, PAMPIPE_VALVE_CLOSED);
    }}
}}

static const pampipe_gait_section *section = 0;

void setup()
{{
    Serial.begin(115200);
    for (uint8_t i = 0; i < PAMPIPE_SEGMENTS; ++i) {{
        pinMode(FILL_PIN[i], OUTPUT);
        pinMode(VENT_PIN[i], OUTPUT);
        set_valve(i, PAMPIPE_VALVE_CLOSED);
    }}
    pampipe_real pressure[PAMPIPE_SEGMENTS];
    int reason = pampipe_required_pressure((pampipe_real){diameter!r},
                                           (pampipe_real){incline!r},
                                           (pampipe_real){friction!r},
                                           PAMPIPE_MISSION_PAYLOAD_KG, pressure);
    Serial.print({reason_label});
    Serial.println(reason);
    for (uint8_t i = 0; i < PAMPIPE_SEGMENTS; ++i) {{
        Serial.print(pampipe_segment_name[i]);
        Serial.print(" needs ");
        Serial.print(pressure[i] / 1000, 3);
        Serial.println(" kPa");
    }}
    for (int s = 0; s < PAMPIPE_SECTIONS && section == 0; ++s) {{
        if (pampipe_gait[s].reason == PAMPIPE_OK) {{
            section = &pampipe_gait[s];
        }}
    }}
}}

void loop()
{{
    if (section == 0) {{
        return; /* no section of the route can be crossed */
    }}
    for (uint8_t k = 1; k < PAMPIPE_GAIT_STEPS; ++k) {{
        Serial.print("step ");
        Serial.println(pampipe_step_name[k]);
        walk_step(&section->step[k]);
    }}
}}
"""
