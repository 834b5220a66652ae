//! Files in: map loaders (MovingAI, ROS YAML + PGM, PNG, ASCII,
//! ValetudoMap JSON) and
//! MovingAI scenarios. Uses the core only.

pub mod maps;
pub mod scen;
pub mod store;
pub mod valetudo;
