pub struct SphereView;
