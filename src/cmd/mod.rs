pub mod list;
pub mod merge;
pub mod papers;
pub mod pipe;
pub mod reference;
pub mod report;
pub mod reproduce;
pub mod run;
pub mod scaling;
pub mod stress;
pub mod validate;
pub mod worker;

use anyhow::{Result, bail};

/// Parses `N` (square) or `WxH`.
pub fn parse_res(s: &str) -> Result<(u32, u32)> {
    let parse = |t: &str| -> Result<u32> {
        let v: u32 = t
            .trim()
            .parse()
            .map_err(|_| anyhow::anyhow!("--res: '{s}' is not N or WxH (e.g. 512 or 640x360)"))?;
        if v == 0 || v > 16384 {
            bail!("--res: {v} is outside 1..=16384");
        }
        Ok(v)
    };
    match s.split_once(['x', 'X']) {
        Some((w, h)) => Ok((parse(w)?, parse(h)?)),
        None => {
            let n = parse(s)?;
            Ok((n, n))
        }
    }
}
