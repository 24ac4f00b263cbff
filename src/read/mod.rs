//! Reading paintings as evidence of a material: what the painter meant, told from what the
//! brush did.

pub mod lobe;
