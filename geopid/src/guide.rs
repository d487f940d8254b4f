#![doc = include_str!("../guide/00-preface.md")]

pub mod first_flight {
    #![doc = include_str!("../guide/01-first-flight.md")]
}
pub mod scenes {
    #![doc = include_str!("../guide/02-scenes.md")]
}
pub mod vehicle {
    #![doc = include_str!("../guide/03-vehicle.md")]
}
pub mod flight_mode {
    #![doc = include_str!("../guide/04-flight-mode.md")]
}
pub mod references {
    #![doc = include_str!("../guide/05-references.md")]
}
pub mod integrators {
    #![doc = include_str!("../guide/06-integrators.md")]
    #![doc = include_str!("../guide/figures/work-precision.svg")]
}
pub mod monte_carlo {
    #![doc = include_str!("../guide/07-monte-carlo.md")]
}
pub mod gradients {
    #![doc = include_str!("../guide/08-gradients.md")]
}
pub mod python {
    #![doc = include_str!("../guide/09-python.md")]
}
pub mod c_and_firmware {
    #![doc = include_str!("../guide/10-c-and-firmware.md")]
}
pub mod validation {
    #![doc = include_str!("../guide/11-validation.md")]
}
pub mod performance {
    #![doc = include_str!("../guide/12-performance.md")]
}
pub mod design {
    #![doc = include_str!("../guide/13-design.md")]
}
pub mod flying_on_sensors {
    #![doc = include_str!("../guide/14-sensors.md")]
    #![doc = include_str!("../guide/figures/sensing.md")]
}
pub mod missions {
    #![doc = include_str!("../guide/15-missions.md")]
    #![doc = include_str!("../guide/figures/missions.md")]
}
pub mod flying_on_an_estimate {
    #![doc = include_str!("../guide/16-estimation.md")]
    #![doc = include_str!("../guide/figures/estimation-position.svg")]
    #![doc = include_str!("../guide/figures/estimation-tracking.svg")]
    #![doc = include_str!("../guide/figures/estimation-recovery.svg")]
    #![doc = include_str!("../guide/figures/estimation.md")]
}
