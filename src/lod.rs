//! Level-of-detail reduction of long series for plotting (in progress).
