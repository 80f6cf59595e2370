//! A scratch test's conclusions from its runs: Archard's law fitted at small loads and the shear
//! hardness H_l = dF_x / dA_z (paper 001 section 3.1, Figs. 3 and 10).

use super::{ArchardFit, ScratchResult, ScratchRun, ShearHardness, WEARING};

impl ScratchResult {
    /// Collects the runs of a test (in the config's load order), fits Archard's law at small loads
    /// (up to three times the threshold) and the shear hardness.
    pub fn collect(runs: Vec<ScratchRun>) -> ScratchResult {
        let mut order: Vec<usize> = (0..runs.len()).collect();
        order.sort_by(|&a, &b| runs[a].load.total_cmp(&runs[b].load));
        let wearing: Vec<usize> = order
            .iter()
            .copied()
            .skip_while(|&k| runs[k].wear_coefficient() < WEARING)
            .collect();
        let archard = archard(&runs, &wearing, 3.0);
        let shear_hardness = (wearing.len() >= 2).then(|| {
            let pts: Vec<[f64; 2]> = wearing
                .iter()
                .take(5)
                .map(|&k| [runs[k].contact_area, runs[k].lateral_force])
                .collect();
            let (slope, intercept) = fit_line(&pts);
            let r = &runs[wearing[0]];
            ShearHardness {
                slope,
                intercept,
                reference: r.mu_a * r.hardness,
                threshold_load: r.load,
                points: pts,
            }
        });
        ScratchResult {
            loads: runs.iter().map(|r| r.load).collect(),
            wear_per_distance: runs.iter().map(|r| r.wear_per_distance).collect(),
            archard,
            shear_hardness,
            runs,
        }
    }
}

/// Archard's line through the wearing runs `wearing` (by increasing load) up to `span` times the
/// threshold (at least two runs).
fn archard(runs: &[ScratchRun], wearing: &[usize], span: f64) -> Option<ArchardFit> {
    let first = *wearing.first()?;
    let limit = span * runs[first].load;
    let pts: Vec<[f64; 2]> = wearing
        .iter()
        .map(|&k| [runs[k].load, runs[k].wear_per_distance])
        .filter(|p| p[0] <= limit)
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let (slope, b) = fit_line(&pts);
    let mean = pts.iter().map(|p| p[1]).sum::<f64>() / pts.len() as f64;
    let (res, tot) = pts.iter().fold((0.0, 0.0), |(r, t), p| {
        (
            r + (p[1] - slope * p[0] - b).powi(2),
            t + (p[1] - mean).powi(2),
        )
    });
    let last = &runs[*wearing.last()?];
    Some(ArchardFit {
        threshold_load: runs[first].load,
        last_load: pts[pts.len() - 1][0],
        slope,
        onset_load: -b / slope,
        r2: if tot > 0.0 { 1.0 - res / tot } else { 1.0 },
        points: pts.len(),
        excess_at_largest: last.wear_per_distance / (slope * last.load + b),
    })
}

/// Least-squares line y = a x + b through `pts`.
pub fn fit_line(pts: &[[f64; 2]]) -> (f64, f64) {
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p[0]).sum::<f64>() / n,
        pts.iter().map(|p| p[1]).sum::<f64>() / n,
    );
    let sxy: f64 = pts.iter().map(|p| (p[0] - mx) * (p[1] - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p[0] - mx).powi(2)).sum();
    let a = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    (a, my - a * mx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_through_points_is_found() {
        let (a, b) = fit_line(&[[1.0, 3.0], [2.0, 5.0], [4.0, 9.0]]);
        assert!((a - 2.0).abs() < 1e-12 && (b - 1.0).abs() < 1e-12);
    }
}
