//! `brdfpaint bench`.

use crate::error::{Error, Result};

pub(super) fn run(json: bool, quick: bool) -> Result<()> {
    let cases = crate::bench::factor_cases(quick)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&cases).map_err(|e| Error::input(e.to_string()))?);
    } else {
        print!("{}", crate::bench::table(&cases));
        println!("solve: one RGB refit (log mapping, solve, tables). Thesis: P4 2003, SVD pre-inversion and its fast factorization.");
    }
    Ok(())
}
