/// One MERL material's published analytic fit.
#[derive(Clone, Debug)]
pub struct MerlFit;
/// The table of fits.
#[derive(Clone, Debug)]
pub struct MerlFits;
