/// A measured BRDF in the MERL binary layout.
#[derive(Clone, Debug)]
pub struct Merl;
