//! The mission report as JSON: the derived ratios, and the counters, the
//! localisation's figures and the faults under the names the JSON uses.

use super::mission::MissionReport;

/// The report as JSON.
pub fn report_json(rep: &MissionReport) -> serde_json::Value {
    let mut v = serde_json::to_value(rep).unwrap_or_default();
    v["sim_speed"] = serde_json::json!(rep.sim_time_s / rep.wall_time_s.max(1e-9));
    // Charging is not cleaning: both ratios are of the cleaning time.
    v["time_vs_ideal"] = serde_json::json!(rep.cleaning_time_s / rep.ideal_time_s.max(1e-9));
    v["time_vs_area_ideal"] = serde_json::json!(rep.cleaning_time_s / rep.floor_time_s.max(1e-9));
    v
}

/// The counters the report shows (names as in the JSON).
#[derive(serde::Serialize)]
struct CountersJson {
    dwa_no_admissible: u32,
    detours: u32,
    replans: u32,
    /// Legs planned again because the growing map came to block them
    /// (unknown mode; left out when 0).
    #[serde(skip_serializing_if = "is_zero")]
    stale_legs: u32,
    guard_ticks: u32,
    escape_ticks: u32,
    abandoned_retries: u32,
    retried: u32,
    scans: u32,
    plan_steps: u32,
    /// Local minima the potential field met (only with `--local apf`;
    /// left out when 0).
    #[serde(skip_serializing_if = "is_zero")]
    apf_local_minima: u32,
    /// Long ways routed on the planning cells (only at the firmware's
    /// capacity; left out when 0).
    #[serde(skip_serializing_if = "is_zero")]
    routes: u32,
    /// Bumper contacts the executive handled (left out when 0).
    #[serde(skip_serializing_if = "is_zero")]
    bumps: u32,
    /// Evidence cells it marked for them (left out when 0).
    #[serde(skip_serializing_if = "is_zero")]
    bump_marks: u32,
    /// Evidence cells marked where a wheel stalled with nothing in sight
    /// (left out when 0).
    #[serde(skip_serializing_if = "is_zero")]
    stall_marks: u32,
}

fn is_zero(n: &u32) -> bool {
    *n == 0
}

pub(super) fn is_zero_usize(n: &usize) -> bool {
    *n == 0
}

pub(super) fn counters_json<S: serde::Serializer>(
    c: &robovac::mission::Counters,
    s: S,
) -> Result<S::Ok, S::Error> {
    serde::Serialize::serialize(
        &CountersJson {
            dwa_no_admissible: c.dwa_no_admissible,
            detours: c.detours,
            replans: c.replans,
            stale_legs: c.stale_legs,
            guard_ticks: c.guard_ticks,
            escape_ticks: c.escapes,
            abandoned_retries: c.abandoned_retries,
            retried: c.retried,
            scans: c.scans,
            plan_steps: c.plan_steps,
            apf_local_minima: c.apf_minima,
            routes: c.routes,
            bumps: c.bumps,
            bump_marks: c.bump_marks,
            stall_marks: c.stall_marks,
        },
        s,
    )
}

pub(super) fn loc_json<S: serde::Serializer>(
    c: &robovac::localize::LocStats,
    s: S,
) -> Result<S::Ok, S::Error> {
    s.collect_map([
        ("matches", c.matches),
        ("accepted", c.accepted),
        ("partial", c.partial),
        ("rejected", c.rejected),
        ("lost", c.lost),
        ("relocalised", c.relocalised),
        ("reloc_failed", c.reloc_failed),
    ])
}

pub(super) fn faults_json<S: serde::Serializer>(
    f: &[(String, u64)],
    s: S,
) -> Result<S::Ok, S::Error> {
    s.collect_map(f.iter().map(|(k, v)| (k, v)))
}
