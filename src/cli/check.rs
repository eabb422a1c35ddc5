//! `dalembert check`: read a candidate trajectory, ask the oracle, print a verdict table.

use super::SceneArgs;
use dalembert::oracle::{check_trajectory, CheckOptions};
use dalembert::protocol::{self, intervals, Session};
use dalembert::Error;
use inari::Interval;
use serde_json::{json, Value};

/// Returns the text to print and whether the check passed (exit 0) or proved the tolerance
/// exceeded (exit 1); an undecided comparison is `Error::Uncertified` (exit 3).
pub fn run(
    scene: &SceneArgs,
    h: &str,
    file: &str,
    tol: Option<&str>,
    no_pairs: bool,
    as_json: bool,
) -> Result<(String, bool), Error> {
    let spec = super::scene_spec(scene)?;
    let model = Session::default().model(&spec)?;
    let h = protocol::parse_num("--h", h)?;
    let tol = tol.map(|t| protocol::parse_num("--tol", t)).transpose()?;
    let text = std::fs::read_to_string(file)
        .map_err(|e| Error::input(format!("--trajectory: cannot read `{file}`: {e}")))?;
    let q = parse_trajectory(&text, model.n)?;
    let opts = CheckOptions {
        pairs: !no_pairs,
        ..CheckOptions::default()
    };
    let v = check_trajectory(&model, h, &q, &opts)?;
    let passed = match tol {
        None => true,
        Some(t) if v.max_distance.sup() <= t => true,
        Some(t) if v.max_distance.inf() > t => false,
        Some(t) => {
            return Err(Error::uncertified(format!(
                "undecided: the certified distance [{:e}, {:e}] straddles --tol {t:e}",
                v.max_distance.inf(),
                v.max_distance.sup()
            )))
        }
    };
    let out = if as_json {
        json!({
            "distance": intervals(&v.distance),
            "max_distance": intervals(&[v.max_distance])[0],
            "defect": v.defect.iter().map(|d| intervals(d)).collect::<Vec<_>>(),
            "energy_error": intervals(&v.energy_error),
            "passed": passed,
        })
        .to_string()
    } else {
        table(
            &v.distance,
            &v.defect,
            &v.energy_error,
            v.max_distance,
            passed,
            tol,
        )
    };
    Ok((out, passed))
}

fn table(
    dist: &[Interval],
    defect: &[Vec<Interval>],
    energy: &[Interval],
    max: Interval,
    passed: bool,
    tol: Option<f64>,
) -> String {
    let mut s = format!(
        "{:>6} {:>24} {:>24} {:>24}\n",
        "k", "|q_k - q^e_k| <=", "defect(q_k,q_k+1) in", "energy error in"
    );
    for (k, d) in dist.iter().enumerate() {
        let def = defect
            .get(k)
            .map(|s| {
                s.iter()
                    .map(|x| format!("[{:.2e},{:.2e}]", x.inf(), x.sup()))
                    .collect::<Vec<_>>()
                    .join(" ")
            })
            .unwrap_or_default();
        let en = energy
            .get(k)
            .map(|e| format!("[{:.2e},{:.2e}]", e.inf(), e.sup()))
            .unwrap_or_default();
        s.push_str(&format!("{k:>6} {:>24.3e} {def:>24} {en:>24}\n", d.sup()));
    }
    s.push_str(&format!("max distance <= {:.3e}", max.sup()));
    if let Some(t) = tol {
        s.push_str(&format!(
            "; tolerance {t:e}: {}",
            if passed { "PASS" } else { "FAIL (proved)" }
        ));
    }
    s
}

/// JSON `{"q": [[..]..]}` (e.g. `integrate --json` output) or `[[..]..]`, or CSV.
fn parse_trajectory(text: &str, n: usize) -> Result<Vec<Vec<f64>>, Error> {
    let t = text.trim_start();
    if t.starts_with('{') || t.starts_with('[') {
        let v: Value = serde_json::from_str(t)
            .map_err(|e| Error::input(format!("--trajectory: not JSON: {e}")))?;
        let rows = v.get("q").unwrap_or(&v);
        let rows = rows
            .as_array()
            .ok_or_else(|| Error::input("--trajectory: expected an array of configurations"))?;
        return rows
            .iter()
            .map(|r| {
                r.as_array()
                    .map(|a| a.iter().filter_map(|x| x.as_f64()).collect::<Vec<f64>>())
                    .filter(|a| a.len() == n)
                    .ok_or_else(|| {
                        Error::input(format!("--trajectory: each q_k needs {n} numbers"))
                    })
            })
            .collect();
    }
    let mut lines = t.lines().filter(|l| !l.trim().is_empty()).peekable();
    let mut skip_k = false;
    if let Some(first) = lines.peek() {
        let cells: Vec<&str> = first.split(',').map(str::trim).collect();
        if cells.iter().any(|c| c.parse::<f64>().is_err()) {
            skip_k = cells.first() == Some(&"k");
            lines.next();
        }
    }
    lines
        .map(|l| {
            let cells: Vec<f64> = l
                .split(',')
                .skip(usize::from(skip_k))
                .take(n)
                .map(|c| protocol::parse_num("--trajectory", c))
                .collect::<Result<_, _>>()?;
            if cells.len() == n {
                Ok(cells)
            } else {
                Err(Error::input(format!(
                    "--trajectory: a CSV row needs {n} numbers"
                )))
            }
        })
        .collect()
}
