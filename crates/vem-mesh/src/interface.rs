//! Interface node insertion: makes two facing boundary parts node-to-node.
